/* sampler.c - the 4D points of the sampler (see sampler.h). */
#include "core/sampler.h"

/* Direction numbers of the third and fourth Sobol' dimensions (Joe & Kuo 2008, primitive
 * polynomials x^2 + x + 1 with m = 1, 3 and x^3 + x + 1 with m = 1, 3, 1), grouped by nibble:
 * entry [d][k][n] is the XOR of the direction numbers of the set bits of n placed at bits
 * 4k .. 4k + 3 of the index. (Generated from the recurrence v_i = v_{i-s} ^ (v_{i-s} >> s) ^
 * sum_k a_k v_{i-k}; tests/test_sampler.c checks them against it.) */
const uint32_t rad_sobol_nibbles[2][8][16] = {
    {/* the third dimension */
        {0x00000000u, 0x80000000u, 0xc0000000u, 0x40000000u, 0x60000000u, 0xe0000000u,
         0xa0000000u, 0x20000000u, 0x90000000u, 0x10000000u, 0x50000000u, 0xd0000000u,
         0xf0000000u, 0x70000000u, 0x30000000u, 0xb0000000u},
        {0x00000000u, 0xe8000000u, 0x5c000000u, 0xb4000000u, 0x8e000000u, 0x66000000u,
         0xd2000000u, 0x3a000000u, 0xc5000000u, 0x2d000000u, 0x99000000u, 0x71000000u,
         0x4b000000u, 0xa3000000u, 0x17000000u, 0xff000000u},
        {0x00000000u, 0x68800000u, 0x9cc00000u, 0xf4400000u, 0xee600000u, 0x86e00000u,
         0x72a00000u, 0x1a200000u, 0x55900000u, 0x3d100000u, 0xc9500000u, 0xa1d00000u,
         0xbbf00000u, 0xd3700000u, 0x27300000u, 0x4fb00000u},
        {0x00000000u, 0x80680000u, 0xc09c0000u, 0x40f40000u, 0x60ee0000u, 0xe0860000u,
         0xa0720000u, 0x201a0000u, 0x90550000u, 0x103d0000u, 0x50c90000u, 0xd0a10000u,
         0xf0bb0000u, 0x70d30000u, 0x30270000u, 0xb04f0000u},
        {0x00000000u, 0xe8808000u, 0x5cc0c000u, 0xb4404000u, 0x8e606000u, 0x66e0e000u,
         0xd2a0a000u, 0x3a202000u, 0xc5909000u, 0x2d101000u, 0x99505000u, 0x71d0d000u,
         0x4bf0f000u, 0xa3707000u, 0x17303000u, 0xffb0b000u},
        {0x00000000u, 0x6868e800u, 0x9c9c5c00u, 0xf4f4b400u, 0xeeee8e00u, 0x86866600u,
         0x7272d200u, 0x1a1a3a00u, 0x5555c500u, 0x3d3d2d00u, 0xc9c99900u, 0xa1a17100u,
         0xbbbb4b00u, 0xd3d3a300u, 0x27271700u, 0x4f4fff00u},
        {0x00000000u, 0x8000e880u, 0xc0005cc0u, 0x4000b440u, 0x60008e60u, 0xe00066e0u,
         0xa000d2a0u, 0x20003a20u, 0x9000c590u, 0x10002d10u, 0x50009950u, 0xd00071d0u,
         0xf0004bf0u, 0x7000a370u, 0x30001730u, 0xb000ffb0u},
        {0x00000000u, 0xe8006868u, 0x5c009c9cu, 0xb400f4f4u, 0x8e00eeeeu, 0x66008686u,
         0xd2007272u, 0x3a001a1au, 0xc5005555u, 0x2d003d3du, 0x9900c9c9u, 0x7100a1a1u,
         0x4b00bbbbu, 0xa300d3d3u, 0x17002727u, 0xff004f4fu},
    },
    {/* the fourth dimension */
        {0x00000000u, 0x80000000u, 0xc0000000u, 0x40000000u, 0x20000000u, 0xa0000000u,
         0xe0000000u, 0x60000000u, 0x50000000u, 0xd0000000u, 0x90000000u, 0x10000000u,
         0x70000000u, 0xf0000000u, 0xb0000000u, 0x30000000u},
        {0x00000000u, 0xf8000000u, 0x74000000u, 0x8c000000u, 0xa2000000u, 0x5a000000u,
         0xd6000000u, 0x2e000000u, 0x93000000u, 0x6b000000u, 0xe7000000u, 0x1f000000u,
         0x31000000u, 0xc9000000u, 0x45000000u, 0xbd000000u},
        {0x00000000u, 0xd8800000u, 0x25400000u, 0xfdc00000u, 0x59e00000u, 0x81600000u,
         0x7ca00000u, 0xa4200000u, 0xe6d00000u, 0x3e500000u, 0xc3900000u, 0x1b100000u,
         0xbf300000u, 0x67b00000u, 0x9a700000u, 0x42f00000u},
        {0x00000000u, 0x78080000u, 0xb40c0000u, 0xcc040000u, 0x82020000u, 0xfa0a0000u,
         0x360e0000u, 0x4e060000u, 0xc3050000u, 0xbb0d0000u, 0x77090000u, 0x0f010000u,
         0x41070000u, 0x390f0000u, 0xf50b0000u, 0x8d030000u},
        {0x00000000u, 0x208f8000u, 0x51474000u, 0x71c8c000u, 0xfbea2000u, 0xdb65a000u,
         0xaaad6000u, 0x8a22e000u, 0x75d93000u, 0x5556b000u, 0x249e7000u, 0x0411f000u,
         0x8e331000u, 0xaebc9000u, 0xdf745000u, 0xfffbd000u},
        {0x00000000u, 0xa0858800u, 0x914e5400u, 0x31cbdc00u, 0xdbe79e00u, 0x7b621600u,
         0x4aa9ca00u, 0xea2c4200u, 0x25db6d00u, 0x855ee500u, 0xb4953900u, 0x1410b100u,
         0xfe3cf300u, 0x5eb97b00u, 0x6f72a700u, 0xcff72f00u},
        {0x00000000u, 0x58800080u, 0xe54000c0u, 0xbdc00040u, 0x79e00020u, 0x216000a0u,
         0x9ca000e0u, 0xc4200060u, 0xb6d00050u, 0xee5000d0u, 0x53900090u, 0x0b100010u,
         0xcf300070u, 0x97b000f0u, 0x2a7000b0u, 0x72f00030u},
        {0x00000000u, 0x800800f8u, 0xc00c0074u, 0x4004008cu, 0x200200a2u, 0xa00a005au,
         0xe00e00d6u, 0x6006002eu, 0x50050093u, 0xd00d006bu, 0x900900e7u, 0x1001001fu,
         0x70070031u, 0xf00f00c9u, 0xb00b0045u, 0x300300bdu},
    },
};

void rad_sampler_point4_bits(uint64_t seed, uint64_t index, uint32_t dimension, uint32_t out[4]) {
    uint32_t shuffled;
    uint64_t h = rad_sampler_dimension_hash(seed, index, dimension, &shuffled);
    uint64_t g = rad_mix64(h + 0x2545f4914f6cdd1dull);
    uint64_t f = rad_mix64(g + 0x2545f4914f6cdd1dull);
    uint32_t value[2] = {0, 0};
    for (int k = 0; k < 8; ++k) {
        uint32_t nibble = (shuffled >> (4 * k)) & 15u;
        value[0] ^= rad_sobol_nibbles[0][k][nibble];
        value[1] ^= rad_sobol_nibbles[1][k][nibble];
    }
    out[0] = rad_reverse_bits32(rad_owen_hash_reversed(shuffled, (uint32_t)(h >> 32)));
    out[1] = rad_reverse_bits32(
        rad_owen_hash_reversed(rad_sobol_second_reversed(shuffled), (uint32_t)g));
    out[2] = rad_owen_scramble(value[0], (uint32_t)(g >> 32));
    out[3] = rad_owen_scramble(value[1], (uint32_t)f);
}
