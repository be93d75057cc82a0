/* hash_index.c - the open-addressing hash index of hash_index.h (linear probing, Fibonacci
 * hashing of the slot). */
#include "core/hash_index.h"

uint64_t rad_hash_string(uint64_t hash, const char *text) {
    for (const unsigned char *c = (const unsigned char *)text; *c; ++c)
        hash = (hash ^ *c) * 0x100000001b3ull;
    return hash;
}

uint64_t rad_hash_pair(uint64_t a, uint64_t b) { return (a << 32 | a >> 32) ^ b; }

/* Fibonacci hashing: the top bits of hash * 2^64/phi, which depend on every bit of the hash. */
static size_t home_slot(uint64_t hash, unsigned bits) {
    return (size_t)((hash * 0x9e3779b97f4a7c15ull) >> (64 - bits));
}

size_t rad_hash_index_next(const rad_hash_index *index, uint64_t hash, size_t *slot) {
    if (!index->slots) return SIZE_MAX;
    size_t mask = ((size_t)1 << index->bits) - 1;
    size_t s = *slot == SIZE_MAX ? home_slot(hash, index->bits) : (*slot + 1) & mask;
    for (; index->slots[s].item; s = (s + 1) & mask)
        if (index->slots[s].hash == hash) {
            *slot = s;
            return index->slots[s].item - 1;
        }
    return SIZE_MAX;
}

rad_status rad_hash_index_insert(rad_context *ctx, rad_hash_index *index, uint64_t hash, size_t item) {
    size_t capacity = index->slots ? (size_t)1 << index->bits : 0;
    if (2 * (index->count + 1) > capacity) {
        unsigned bits = index->slots ? index->bits + 1 : 6;
        struct rad_hash_slot *slots = rad_alloc_zero(ctx, (size_t)1 << bits, sizeof *slots);
        if (!slots) return RAD_ERROR_NO_MEMORY;
        for (size_t i = 0; i < capacity; ++i) {
            if (!index->slots[i].item) continue;
            size_t s = home_slot(index->slots[i].hash, bits);
            while (slots[s].item) s = (s + 1) & (((size_t)1 << bits) - 1);
            slots[s] = index->slots[i];
        }
        rad_free(ctx, index->slots);
        index->slots = slots;
        index->bits = bits;
    }
    size_t mask = ((size_t)1 << index->bits) - 1, s = home_slot(hash, index->bits);
    while (index->slots[s].item) s = (s + 1) & mask;
    index->slots[s] = (struct rad_hash_slot){hash, item + 1};
    index->count++;
    return RAD_OK;
}

void rad_hash_index_replace(rad_hash_index *index, size_t slot, size_t item) {
    index->slots[slot].item = item + 1;
}

void rad_hash_index_free(rad_context *ctx, rad_hash_index *index) {
    rad_free(ctx, index->slots);
    *index = (rad_hash_index){0};
}
