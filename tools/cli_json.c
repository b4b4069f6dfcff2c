/* cli_json.c — the one JSON writer of the command line: documents are
 * built as cJSON trees (Debian's libcjson; no hand-written escaping) and
 * written through a temporary name. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

cJSON *cli_json_group_sizes(const spr_groups *g)
{
    cJSON *arr = cJSON_CreateArray();
    for (int k = 0; arr && k < g->K; k++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(g->start[k + 1] - g->start[k]));
    return arr;
}
