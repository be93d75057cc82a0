/* sampler.h - low-discrepancy samples: Owen-scrambled Sobol' points, padded dimension by
 * dimension (docs/pathtracing.md, "Sampling").
 *
 * Each pixel draws its samples as points of the first two Sobol' dimensions (Sobol' 1967), the
 * (0,2)-sequence whose first 2^m points put exactly one point in every elementary interval of
 * area 2^-m. Every 2D "dimension" a renderer asks for (the pixel position, an emitter sample, a
 * BSDF sample, ...) gets its own copy of that sequence, decorrelated from the others as Burley
 * (2020, "Practical hash-based Owen scrambling", JCGT 9(4)) does it:
 *   - the sample index is shuffled by a nested uniform scramble (a random permutation that maps
 *     each aligned block of 2^m indices onto another aligned block, so any power-of-two prefix
 *     is still a (0,m,2)-net);
 *   - each coordinate is Owen-scrambled (Owen 1995): bit k of the value is flipped by a random
 *     function of the bits above it. The hash that does this on the bit-reversed value is the
 *     Laine-Karras construction (Laine & Karras 2011, "Stratified sampling for stochastic
 *     transparency") with better constants (N. Vegdahl 2021, cited by pbrt-v4);
 *   - the seeds of a dimension come from a hash of (image seed, dimension), and pixels own
 *     aligned runs of a single sequence in Morton order (rad_sampler_pixel_index), so blocks of
 *     pixels are stratified as a whole (Ahmed & Wonka 2020; pbrt-v4's ZSobol).
 * Owen scrambling keeps the net property and makes each point uniform on [0,1)^2, so estimates
 * stay unbiased, with variance falling faster than 1/N for smooth integrands (Owen 1997).
 * Everything is a pure function of (seed, index, dimension): the image does not depend
 * on the thread count or the order in which pixels are drawn.
 *
 * The second Sobol' dimension uses direction numbers v_0 = 2^31, v_{k+1} = v_k ^ (v_k >> 1):
 * bit 31 - t of v_k is binomial(k, t) mod 2, which by Lucas' theorem is "t is a bit subset of
 * k"; so on the bit-reversed value it is a superset sum over 5-bit positions, five shift-xor
 * steps instead of a loop over the index bits (sobol_second_reversed). */
#ifndef RAD_CORE_SAMPLER_H
#define RAD_CORE_SAMPLER_H

#include <stdint.h>

typedef struct rad_sampler {
    uint64_t seed;      /* the image's seed */
    uint64_t index;     /* which point of the image's sequence (rad_sampler_pixel_index) */
    uint32_t dimension; /* the next 2D dimension to hand out */
} rad_sampler;

static inline uint32_t rad_reverse_bits32(uint32_t x) {
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
    return x;
}

/* A 64-bit mix with full avalanche (the finaliser of MurmurHash3). */
static inline uint64_t rad_mix64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    x ^= x >> 33;
    return x;
}

/* On a bit-reversed value: bit k is flipped by a function of the bits below it (and the seed),
 * so on the value itself each bit depends only on the bits above it - an Owen scramble. Every
 * step is a bijection: adding, and x ^= x * even (bit k changes by lower bits only). */
static inline uint32_t rad_owen_hash_reversed(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* Owen scramble of a 32-bit fraction (a nested uniform scramble, Burley 2020). */
static inline uint32_t rad_owen_scramble(uint32_t x, uint32_t seed) {
    return rad_reverse_bits32(rad_owen_hash_reversed(rad_reverse_bits32(x), seed));
}

/* The second Sobol' dimension of point `index`, bit-reversed (see the top of this file). */
static inline uint32_t rad_sobol_second_reversed(uint32_t index) {
    uint32_t r = index;
    r ^= (r >> 1) & 0x55555555u;
    r ^= (r >> 2) & 0x33333333u;
    r ^= (r >> 4) & 0x0f0f0f0fu;
    r ^= (r >> 8) & 0x00ff00ffu;
    r ^= (r >> 16) & 0x0000ffffu;
    return r;
}

/* Morton order: the bits of x and y interleaved (x in the even bits), 32 bits of each. */
static inline uint64_t rad_morton2(uint32_t x, uint32_t y) {
    uint64_t m[2] = {x, y};
    for (int k = 0; k < 2; ++k) {
        m[k] = (m[k] | (m[k] << 16)) & 0x0000ffff0000ffffull;
        m[k] = (m[k] | (m[k] << 8)) & 0x00ff00ff00ff00ffull;
        m[k] = (m[k] | (m[k] << 4)) & 0x0f0f0f0f0f0f0f0full;
        m[k] = (m[k] | (m[k] << 2)) & 0x3333333333333333ull;
        m[k] = (m[k] | (m[k] << 1)) & 0x5555555555555555ull;
    }
    return m[0] | (m[1] << 1);
}

/* The index of sample `sample` of pixel (x, y) when each pixel draws up to `count` samples:
 * (Morton index << ceil(log2 count)) + sample. Pixels then own aligned runs of indices, and so
 * does every aligned square of 2^k x 2^k pixels: the samples of a 4x4 block at 64 spp are one
 * (0,10,2)-net in every dimension, not 16 independent nets (Ahmed & Wonka 2020, "Screen-space
 * blue-noise diffusion of Monte Carlo sampling error via hierarchical ordering of pixels"; pbrt-v4's
 * ZSobolSampler). Images wider than 65535 pixels wrap the Morton index (still unbiased). */
static inline uint64_t rad_sampler_pixel_index(uint32_t x, uint32_t y, uint32_t count,
                                               uint32_t sample) {
    int shift = 0;
    while (shift < 31 && (1u << shift) < count) ++shift;
    return (rad_morton2(x, y) << shift) + sample;
}

static inline rad_sampler rad_sampler_make(uint64_t seed, uint64_t index) {
    rad_sampler s;
    s.seed = rad_mix64(seed ^ 0x9e3779b97f4a7c15ull);
    s.index = index;
    s.dimension = 0;
    return s;
}

/* The hash of a dimension: the shuffle seed in the low half, a scramble seed in the high half.
 * The index is shuffled by a nested uniform scramble of its 64 bits: the high half first, whose
 * result reseeds the low half's, so each bit still depends only on the bits above it. The low 32
 * bits index the Sobol' points; every run of 2^32 indices is scrambled on its own. */
static inline uint64_t rad_sampler_dimension_hash(uint64_t seed, uint64_t index,
                                                  uint32_t dimension, uint32_t *shuffled) {
    uint64_t h = rad_mix64(seed + 0x632be59bd9b4e019ull * ((uint64_t)dimension + 1));
    uint32_t high = (uint32_t)(index >> 32);
    if (high) h = rad_mix64(h ^ rad_owen_scramble(high, (uint32_t)h));
    *shuffled = rad_owen_scramble((uint32_t)index, (uint32_t)h);
    return h;
}

/* The 2D point of a shuffled index under dimension hash h (rad_sampler_dimension_hash). */
static inline void rad_sampler_shuffled_bits(uint32_t shuffled, uint64_t h, uint32_t out[2]) {
    uint64_t g = rad_mix64(h + 0x2545f4914f6cdd1dull);
    /* First Sobol' dimension: the van der Corput sequence, reverse(shuffled); the scramble works
     * on the reversed value, which is `shuffled` itself. */
    out[0] = rad_reverse_bits32(rad_owen_hash_reversed(shuffled, (uint32_t)(h >> 32)));
    out[1] = rad_reverse_bits32(
        rad_owen_hash_reversed(rad_sobol_second_reversed(shuffled), (uint32_t)g));
}

/* Point `index` of 2D dimension `dimension`, as 32-bit fractions. */
static inline void rad_sampler_point_bits(uint64_t seed, uint64_t index, uint32_t dimension,
                                          uint32_t out[2]) {
    uint32_t shuffled;
    uint64_t h = rad_sampler_dimension_hash(seed, index, dimension, &shuffled);
    rad_sampler_shuffled_bits(shuffled, h, out);
}

/* Points index .. index + count - 1 of 2D dimension `dimension`: rad_sampler_point_bits' for
 * each, the dimension's hash made once. The run must not cross a multiple of 2^32 (the hash
 * depends on the index's high half): a pixel's points share it (rad_sampler_pixel_index). */
static inline void rad_sampler_run_bits(uint64_t seed, uint64_t index, int count,
                                        uint32_t dimension, uint32_t (*out)[2]) {
    uint32_t shuffled;
    uint64_t h = rad_sampler_dimension_hash(seed, index, dimension, &shuffled);
    for (int i = 0; i < count; ++i)
        rad_sampler_shuffled_bits(rad_owen_scramble((uint32_t)index + (uint32_t)i, (uint32_t)h), h,
                                  out[i]);
}

/* Point `index` of 4D dimension `dimension`: the first four Sobol' dimensions of one shuffled
 * index, each Owen-scrambled, so the four numbers are stratified jointly (the first four Sobol'
 * dimensions form a (3,4)-sequence), not only in pairs: for integrands that couple two 2D
 * choices, such as the direction leaving one vertex and the emitter point sampled at the next.
 * The third and fourth dimensions use Joe & Kuo's (2008) direction numbers (sampler.c). */
void rad_sampler_point4_bits(uint64_t seed, uint64_t index, uint32_t dimension, uint32_t out[4]);
extern const uint32_t rad_sobol_nibbles[2][8][16]; /* for the tests */

/* 32-bit fraction to [0, 1). */
static inline double rad_sampler_fraction(uint32_t bits) { return (double)bits * 0x1p-32; }

/* The next 2D dimension: two numbers in [0, 1). */
static inline void rad_sampler_2d(rad_sampler *s, double out[2]) {
    uint32_t bits[2];
    rad_sampler_point_bits(s->seed, s->index, s->dimension++, bits);
    out[0] = rad_sampler_fraction(bits[0]);
    out[1] = rad_sampler_fraction(bits[1]);
}

/* The next 4D dimension: four numbers in [0, 1), stratified together. */
static inline void rad_sampler_4d(rad_sampler *s, double out[4]) {
    uint32_t bits[4];
    rad_sampler_point4_bits(s->seed, s->index, s->dimension++, bits);
    for (int k = 0; k < 4; ++k) out[k] = rad_sampler_fraction(bits[k]);
}

#endif
