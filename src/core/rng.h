/* rng.h - PCG32 (O'Neill 2014): a small, fast generator with independent streams, so every
 * parallel task can own a stream derived from (seed, task) and results do not depend on the
 * thread count. */
#ifndef RAD_CORE_RNG_H
#define RAD_CORE_RNG_H

#include <stdint.h>

typedef struct rad_rng {
    uint64_t state;
    uint64_t increment;
} rad_rng;

static inline uint32_t rad_rng_next(rad_rng *rng) {
    uint64_t old = rng->state;
    rng->state = old * 6364136223846793005ull + rng->increment;
    uint32_t shifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rotation = (uint32_t)(old >> 59u);
    return (shifted >> rotation) | (shifted << ((-rotation) & 31u));
}

/* A generator for (seed, stream): the same pair always gives the same sequence. */
static inline rad_rng rad_rng_make(uint64_t seed, uint64_t stream) {
    rad_rng rng = {0u, (stream << 1u) | 1u};
    rad_rng_next(&rng);
    rng.state += seed;
    rad_rng_next(&rng);
    return rng;
}

/* Uniform in [0, 1). */
static inline double rad_rng_uniform(rad_rng *rng) {
    return (double)rad_rng_next(rng) * (1.0 / 4294967296.0);
}

#endif
