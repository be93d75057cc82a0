/* photon_map.c - the photon map's hash grid and its density estimates (see photon_map.h;
 * Jensen 1996, 2001 ch. 6-7). */
#include "render/photon_map.h"

#include "core/sampler.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SAME_SURFACE_COSINE 0.9

/* ---- the packed photon -------------------------------------------------------------------- */

/* A unit vector to `bits` + `bits` octahedral code: projected onto the octahedron |x|+|y|+|z| = 1,
 * the lower half folded over the upper, (x, y) quantised to the nearest of 2^bits levels. */
static uint32_t octahedral_encode(rad_vec3 n, int bits) {
    double sum = fabs(n.x) + fabs(n.y) + fabs(n.z);
    double x = sum > 0 ? n.x / sum : 0, y = sum > 0 ? n.y / sum : 0;
    if (n.z < 0) {
        double fx = (1 - fabs(y)) * (x >= 0 ? 1 : -1), fy = (1 - fabs(x)) * (y >= 0 ? 1 : -1);
        x = fx, y = fy;
    }
    double levels = (double)((1u << bits) - 1);
    /* Rounded to the nearest level: the values are >= 0, so + 0.5 and truncation. */
    uint32_t qx = (uint32_t)((fmin(1, fmax(-1, x)) * 0.5 + 0.5) * levels + 0.5);
    uint32_t qy = (uint32_t)((fmin(1, fmax(-1, y)) * 0.5 + 0.5) * levels + 0.5);
    return qx << bits | qy;
}

rad_vec3 rad_octahedral_decode(uint32_t code, int bits) {
    uint32_t mask = (1u << bits) - 1;
    double levels = (double)mask;
    double x = (double)(code >> bits & mask) / levels * 2 - 1, y = (double)(code & mask) / levels * 2 - 1;
    double z = 1 - fabs(x) - fabs(y);
    double t = z < 0 ? -z : 0;
    x += x >= 0 ? -t : t;
    y += y >= 0 ? -t : t;
    return v3_normalize(v3(x, y, z));
}

rad_photon rad_photon_pack(rad_vec3 position, const double power[3], rad_vec3 normal,
                           rad_vec3 incoming) {
    rad_photon p;
    memset(&p, 0, sizeof p);
    p.position[0] = (float)position.x, p.position[1] = (float)position.y;
    p.position[2] = (float)position.z;
    /* Shared exponent: the largest channel's, so its mantissa is in [2^15, 2^16). */
    double largest = fmax(power[0], fmax(power[1], power[2]));
    if (largest > 0 && isfinite(largest)) {
        int e;
        frexp(largest, &e);
        /* 2^(16 - e) as a double's bits (e within a double's range, so is 16 - e). */
        uint64_t bits = (uint64_t)(16 - e + 1023) << 52;
        double scale;
        memcpy(&scale, &bits, sizeof scale);
        if (largest * scale + 0.5 >= 65536) { /* rounded up to 2^16 */
            ++e;
            scale *= 0.5;
        }
        if (e + 128 >= 1 && e + 128 <= 255) {
            p.exponent = (uint8_t)(e + 128);
            for (int c = 0; c < 3; ++c)
                p.power[c] = power[c] > 0 ? (uint16_t)(power[c] * scale + 0.5) : 0;
        } else if (e + 128 > 255) { /* past 2^127: the largest representable */
            p.exponent = 255;
            for (int c = 0; c < 3; ++c) p.power[c] = power[c] > 0 ? 65535 : 0;
        }
    }
    p.normal = (uint16_t)octahedral_encode(normal, 8);
    uint32_t in = octahedral_encode(incoming, 12);
    p.incoming_high = (uint16_t)(in >> 8);
    p.incoming_low = (uint8_t)(in & 0xff);
    return p;
}

/* ---- the grid ----------------------------------------------------------------------------- */

static int64_t cell_of(double coordinate, double cell) { return (int64_t)floor(coordinate / cell); }

/* The low 21 bits of v spread to every third bit. */
static uint64_t spread3(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

/* A cell's bucket: the low bits of its Morton code (Morton 1966), so neighbouring cells share
 * nearby buckets and the photons sorted by bucket lie in space order: a query's 27 cells, and
 * the queries of photons taken in array order, read memory that is near (cells a period of
 * 2^(m/3) apart per axis share a bucket, which costs only distance tests). */
static uint32_t bucket_of(int64_t cx, int64_t cy, int64_t cz, size_t bucket_count) {
    uint64_t code = spread3((uint64_t)cx) | spread3((uint64_t)cy) << 1 | spread3((uint64_t)cz) << 2;
    return (uint32_t)(code & (bucket_count - 1));
}

rad_status rad_photon_map_build_runs(rad_context *ctx, const rad_photon_run *runs, size_t run_count,
                                     double cell, int threads, rad_photon_map *out) {
    memset(out, 0, sizeof *out);
    out->cell = cell;
    if (!(cell > 0) || !isfinite(cell))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "photon map: the radius must be positive");
    size_t count = 0;
    for (size_t r = 0; r < run_count; ++r) count += runs[r].count;
    if (count > UINT32_MAX - 1)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "photon map: more than 2^32 photons");
    size_t buckets = 1;
    while (buckets < count) buckets <<= 1;
    uint32_t *key = rad_alloc(ctx, count ? count : 1, sizeof *key);
    uint32_t *start = rad_alloc_zero(ctx, buckets + 1, sizeof *start);
    uint32_t *next = rad_alloc(ctx, buckets, sizeof *next);
    size_t *run_first = rad_alloc(ctx, run_count + 1, sizeof *run_first);
    rad_photon *sorted = rad_alloc(ctx, count ? count : 1, sizeof *sorted);
    if (!key || !start || !next || !run_first || !sorted) {
        rad_free(ctx, key);
        rad_free(ctx, start);
        rad_free(ctx, next);
        rad_free(ctx, run_first);
        rad_free(ctx, sorted);
        return RAD_ERROR_NO_MEMORY;
    }
    run_first[0] = 0;
    for (size_t r = 0; r < run_count; ++r) run_first[r + 1] = run_first[r] + runs[r].count;
    /* Each photon's bucket, in parallel, run by run. */
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (long long r = 0; r < (long long)run_count; ++r)
        for (size_t i = 0; i < runs[r].count; ++i) {
            rad_vec3 p = rad_photon_position(&runs[r].photons[i]);
            key[run_first[r] + i] =
                bucket_of(cell_of(p.x, cell), cell_of(p.y, cell), cell_of(p.z, cell), buckets);
        }
    /* A stable counting sort by bucket: the order inside a bucket is the runs' order. */
    for (size_t i = 0; i < count; ++i) ++start[key[i] + 1];
    for (size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    memcpy(next, start, buckets * sizeof *next);
    for (size_t r = 0; r < run_count; ++r)
        for (size_t i = 0; i < runs[r].count; ++i)
            sorted[next[key[run_first[r] + i]]++] = runs[r].photons[i];
    rad_free(ctx, next);
    rad_free(ctx, key);
    rad_free(ctx, run_first);
    out->photons = sorted;
    out->count = count;
    out->bucket_start = start;
    out->bucket_count = buckets;
    return RAD_OK;
}

rad_status rad_photon_map_build(rad_context *ctx, rad_photon *photons, size_t count, double cell,
                                int threads, rad_photon_map *out) {
    rad_photon_run run = {photons, count};
    rad_status status = rad_photon_map_build_runs(ctx, &run, 1, cell, threads, out);
    rad_free(ctx, photons);
    return status;
}

void rad_photon_map_free(rad_context *ctx, rad_photon_map *map) {
    if (!map) return;
    rad_free(ctx, map->photons);
    rad_free(ctx, map->bucket_start);
    memset(map, 0, sizeof *map);
}

/* The distinct buckets of the 27 cells around x, in the order dz, dy, dx from -1 to 1 (with
 * `home_first`, x's own cell first), and each cell's squared distance from x (gap2: no photon of
 * the cell is nearer). The Morton code is the three axes' spread bits or-ed together, so the 27
 * codes come from 9 spread coordinates. Two of the cells share a bucket only when an axis keeps
 * fewer than 2 bits of the code (fewer than 64 buckets: cells 1 or 2 apart differ modulo 4);
 * then the repeats are dropped and every gap is 0 (a bucket stands for more than one cell). */
static int query_cells(const rad_photon_map *map, rad_vec3 x, int home_first, uint32_t buckets[27],
                       double gap2[27]) {
    double cell = map->cell, position[3] = {x.x, x.y, x.z};
    uint64_t spread[3][3], mask = map->bucket_count - 1;
    double gap[3][3];
    for (int a = 0; a < 3; ++a) {
        int64_t c = cell_of(position[a], cell);
        /* Shortened by a billionth of the cell against rounding in the cell's bounds. */
        double below = position[a] - (double)c * cell, slack = 1e-9 * cell;
        double to_lower = fmax(0, below - slack), to_upper = fmax(0, cell - below - slack);
        gap[a][0] = to_lower * to_lower, gap[a][1] = 0, gap[a][2] = to_upper * to_upper;
        for (int d = 0; d < 3; ++d) spread[a][d] = spread3((uint64_t)(c + d - 1)) << a;
    }
    int distinct = map->bucket_count >= 64, n = 0;
    for (int k = home_first ? -1 : 0; k < 27; ++k) {
        if (home_first && k == 13) continue; /* the home cell, already first */
        int cell_index = k < 0 ? 13 : k, dx = cell_index % 3, dy = cell_index / 3 % 3,
            dz = cell_index / 9;
        uint32_t b = (uint32_t)((spread[0][dx] | spread[1][dy] | spread[2][dz]) & mask);
        int seen = 0;
        for (int i = 0; i < n && !distinct && !seen; ++i) seen = buckets[i] == b;
        if (seen) continue;
        gap2[n] = distinct ? gap[0][dx] + gap[1][dy] + gap[2][dz] : 0;
        buckets[n++] = b;
    }
    return n;
}

/* The photon's normal within acos(0.9) of `normal`: its octahedral code decoded without the
 * normalisation (the cosine compared as dot > 0.9 |n|). */
static int same_surface_code(uint16_t code, rad_vec3 normal) {
    double x = (double)(code >> 8) * (2.0 / 255) - 1, y = (double)(code & 0xff) * (2.0 / 255) - 1;
    double z = 1 - fabs(x) - fabs(y);
    double t = z < 0 ? -z : 0;
    x += x >= 0 ? -t : t;
    y += y >= 0 ? -t : t;
    double dot = x * normal.x + y * normal.y + z * normal.z;
    return dot > 0 && dot * dot > SAME_SURFACE_COSINE * SAME_SURFACE_COSINE * (x * x + y * y + z * z);
}

/* The answer for the last normal code asked about (photons on one flat wall share their code,
 * so a query decodes few). */
typedef struct surface_test {
    rad_vec3 normal;
    uint32_t code; /* the last code; above 0xffff: none yet */
    int same;
} surface_test;

static int same_surface(surface_test *test, const rad_photon *p) {
    if (p->normal != test->code) {
        test->code = p->normal;
        test->same = same_surface_code(p->normal, test->normal);
    }
    return test->same;
}

/* A max-heap on distance2 of at most k entries: the k nearest so far. */
static void heap_push(rad_photon_near *heap, size_t *size, size_t k, rad_photon_near item) {
    if (*size == k) {
        if (item.distance2 >= heap[0].distance2) return;
        /* Replace the farthest and sift down. */
        size_t i = 0;
        for (;;) {
            size_t l = 2 * i + 1, r = l + 1, m = i;
            double dm = item.distance2;
            if (l < k && heap[l].distance2 > dm) { m = l; dm = heap[l].distance2; }
            if (r < k && heap[r].distance2 > dm) m = r;
            if (m == i) break;
            heap[i] = heap[m];
            i = m;
        }
        heap[i] = item;
        return;
    }
    size_t i = (*size)++;
    while (i > 0) {
        size_t parent = (i - 1) / 2;
        if (heap[parent].distance2 >= item.distance2) break;
        heap[i] = heap[parent];
        i = parent;
    }
    heap[i] = item;
}

static int near_order(const void *a, const void *b) {
    const rad_photon_near *x = a, *y = b;
    if (x->distance2 != y->distance2) return x->distance2 < y->distance2 ? -1 : 1;
    return x->photon < y->photon ? -1 : x->photon > y->photon; /* ties: array order */
}

size_t rad_photon_map_nearest(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                              double radius, size_t k, rad_photon_near *found, double *radius2) {
    size_t size = rad_photon_map_nearest_heap(map, x, normal, radius, k, found, radius2);
    qsort(found, size, sizeof *found, near_order);
    return size;
}

size_t rad_photon_map_nearest_heap(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                                   double radius, size_t k, rad_photon_near *found,
                                   double *radius2) {
    double r2 = radius * radius;
    *radius2 = r2;
    if (map->count == 0 || k == 0) return 0;
    uint32_t buckets[27];
    double gap2[27];
    /* x's own cell first, so the k-th distance shrinks early and farther cells are skipped. */
    int nb = query_cells(map, x, 1, buckets, gap2);
    surface_test test = {normal, UINT32_MAX, 0};
    size_t size = 0;
    double bound = r2; /* the k-th distance so far: nothing at or past it can enter */
    for (int b = 0; b < nb; ++b) {
        if (gap2[b] >= bound) continue;
        for (uint32_t i = map->bucket_start[buckets[b]]; i < map->bucket_start[buckets[b] + 1]; ++i) {
            const rad_photon *p = &map->photons[i];
            rad_vec3 d = v3_sub(rad_photon_position(p), x);
            double d2 = v3_dot(d, d);
            if (d2 >= bound || !same_surface(&test, p)) continue;
            heap_push(found, &size, k, (rad_photon_near){p, d2});
            if (size == k) bound = found[0].distance2;
        }
    }
    if (size == k) *radius2 = found[0].distance2;
    return size;
}

void rad_photon_map_irradiance(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                               double radius, size_t k, rad_photon_near *scratch, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    if (map->count == 0) return;
    if (k > 0) {
        double r2;
        size_t n = rad_photon_map_nearest_heap(map, x, normal, radius, k, scratch, &r2);
        /* Of k found, the k-th (the heap's first) only sets the radius. */
        size_t first = n == k && k > 1 ? 1 : 0;
        if (!(r2 > 0)) return;
        for (size_t i = first; i < n; ++i) {
            double power[3];
            rad_photon_power(scratch[i].photon, 1, power);
            for (int c = 0; c < 3; ++c) out[c] += power[c];
        }
        for (int c = 0; c < 3; ++c) out[c] /= RAD_PI * r2;
        return;
    }
    double r2 = radius * radius;
    uint32_t buckets[27];
    double gap2[27];
    int nb = query_cells(map, x, 0, buckets, gap2);
    surface_test test = {normal, UINT32_MAX, 0};
    for (int b = 0; b < nb; ++b)
        if (gap2[b] < r2)
            for (uint32_t i = map->bucket_start[buckets[b]]; i < map->bucket_start[buckets[b] + 1];
                 ++i) {
                const rad_photon *p = &map->photons[i];
                rad_vec3 d = v3_sub(rad_photon_position(p), x);
                if (v3_dot(d, d) >= r2 || !same_surface(&test, p)) continue;
                double power[3];
                rad_photon_power(p, 1, power);
                for (int c = 0; c < 3; ++c) out[c] += power[c];
            }
    for (int c = 0; c < 3; ++c) out[c] /= RAD_PI * r2;
}
