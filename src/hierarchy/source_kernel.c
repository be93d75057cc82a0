/* source_kernel.c - the radiosity a link reads from its source, weighed by where its receiver
 * looks.
 *
 * A link r <- s carries F_rs times s's radiosity, and the push-pull makes that the area mean of
 * s's leaves (Hanrahan, Salzman & Aupperle 1991). The exact transfer is the integral of B_s over
 * s weighed by the kernel from r: a large source of uneven light read by a small receiver that
 * sees mostly one side of it (a wall's strip beside the floor, the ceiling's over the walls'
 * tops) takes the mean of the far side too. The oracle cannot see it while the link's
 * BF error passes, and at a fine link error there are many such links, all off the same way:
 * on the Cornell box every surface but the floor came out 0.26-0.29 % dark (the ceiling 0.9 %)
 * and 0.17 % of the lamp's power more escaped than with shooting at 10,000 elements
 * (docs/hierarchical.md, "hcornell2").
 *
 * Here the source's descendants a few levels down, which the refinement made for other links
 * and whose radiosity the push-pull keeps, are weighed by their area times cos cos / r^2 from
 * the receiver's centre to theirs (from its four quadrature points instead: the same surface
 * means to 0.01 %, for four times the work): the link's factor F_rs (visibility
 * included) stays, only the mean it multiplies follows the kernel. The children's own factors
 * from r sum to F_rs when r sees all of s, so this is the transfer of the links one level
 * further down the source, without making them; partly hidden links keep the plain mean (the
 * kernel does not know which descendants are hidden). */
#include "hierarchy/source_kernel.h"

#include <math.h>

static rad_vec3 centre(const rad_hier_node *n) {
    if (n->corner_count == 3)
        return v3_scale(v3_add(v3_add(n->corner[0], n->corner[1]), n->corner[2]), 1.0 / 3);
    return v3_scale(v3_add(v3_add(n->corner[0], n->corner[1]), v3_add(n->corner[2], n->corner[3])),
                    0.25);
}

/* Adds node `index`'s descendants `depth` levels down (or its leaves above that) to the
 * weighed sums, x the receiver's centre. */
static void add_descendants(const rad_hier_node *nodes, uint32_t index, int depth, rad_vec3 x,
                            rad_vec3 nr, rad_vec3 ns, double *weights, double sum[3]) {
    const rad_hier_node *n = &nodes[index];
    if (depth > 0 && n->first_child != RAD_HIER_NO_NODE) {
        for (uint32_t k = 0; k < n->child_count; ++k)
            add_descendants(nodes, n->first_child + k, depth - 1, x, nr, ns, weights, sum);
        return;
    }
    rad_vec3 ray = v3_sub(centre(n), x);
    double r2 = v3_dot(ray, ray);
    double weight = fmax(0, v3_dot(nr, ray)) * fmax(0, -v3_dot(ns, ray)) / (r2 * r2) * n->area;
    *weights += weight;
    for (int c = 0; c < 3; ++c) sum[c] += weight * n->radiosity[c];
}

int rad_hier_source_kernel_mean(const rad_hier_node *nodes, const rad_hier_node *receiver,
                                rad_vec3 nr, uint32_t source, rad_vec3 ns, int depth,
                                double out[3]) {
    const rad_hier_node *s = &nodes[source];
    if (depth <= 0 || s->first_child == RAD_HIER_NO_NODE || s->corner_count == 0 ||
        receiver->corner_count == 0)
        return 0;
    double weights = 0, sum[3] = {0, 0, 0};
    add_descendants(nodes, source, depth, centre(receiver), nr, ns, &weights, sum);
    if (!(weights > 0)) return 0;
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / weights;
    return 1;
}
