/* spr_graph.h — an undirected neighbour graph in CSR form, shared by the
 * neighbour searches (spr_knn.h), grouping and the metrics.
 *
 * Invariant: adj[start[i] … start[i+1]) lists the neighbours j ≠ i of vertex
 * i in ascending order, and j lists i whenever i lists j.
 */
#ifndef SPR_GRAPH_H
#define SPR_GRAPH_H

#include <stddef.h>
#include <stdint.h>

typedef struct spr_graph {
    size_t n;
    uint64_t *start;  /* n + 1 */
    uint32_t *adj;
} spr_graph;
/* Release the arrays; safe on a zeroed graph. */
void spr_graph_free(spr_graph *g);

#endif
