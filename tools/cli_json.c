/* cli_json.c — the one JSON writer of the command line: documents are
 * built as cJSON trees (Debian's libcjson; no hand-written escaping) and
 * written through a temporary name. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static int put_text(FILE *f, const void *user)
{
    const char *s = user;
    size_t n = strlen(s);
    return fwrite(s, 1, n, f) == n && fputc('\n', f) != EOF ? 0 : -1;
}

int cli_write_json(cli_args *a, const char *path, cJSON *root)
{
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) { cli_error(a, "%s: out of memory building JSON", path); return -1; }
    spr_error err = {0};
    int rc = spr__write_atomic(path, put_text, text, &err) ? -1 : 0;
    if (rc) fprintf(stderr, "splatref %s: %s\n", a->cmd, err.msg);
    free(text);
    return rc;
}

cJSON *cli_json_group_sizes(const spr_groups *g)
{
    cJSON *arr = cJSON_CreateArray();
    for (int k = 0; arr && k < g->K; k++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(g->start[k + 1] - g->start[k]));
    return arr;
}
