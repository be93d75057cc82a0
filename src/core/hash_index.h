/* hash_index.h - an open-addressing hash index for readers that look up what they have read
 * (names, pairs of numbers): slots hold a 64-bit hash and an item number, so a lookup is O(1)
 * instead of a scan. The index stores no keys; the caller confirms a hash match against the item
 * itself (rad_hash_index_next walks every item stored under a hash). */
#ifndef RAD_CORE_HASH_INDEX_H
#define RAD_CORE_HASH_INDEX_H

#include "core/context.h"

#include <stddef.h>
#include <stdint.h>

typedef struct rad_hash_index {
    struct rad_hash_slot { uint64_t hash; size_t item; } *slots; /* item + 1; 0: an empty slot */
    unsigned bits; /* 2^bits slots, or none before the first insert */
    size_t count;
} rad_hash_index;

/* FNV-1a over the bytes of a string, continuing from `hash` (RAD_HASH_START to begin). */
#define RAD_HASH_START 0xcbf29ce484222325ull
uint64_t rad_hash_string(uint64_t hash, const char *text);
/* A hash of an ordered pair of numbers. */
uint64_t rad_hash_pair(uint64_t a, uint64_t b);

/* Walks the items stored under `hash`: call with *slot = SIZE_MAX to start; returns the next
 * item, or SIZE_MAX when there are no more. */
size_t rad_hash_index_next(const rad_hash_index *index, uint64_t hash, size_t *slot);
/* Adds `item` under `hash` (another item under the same hash stays), growing the table to keep
 * it at most half full; RAD_ERROR_NO_MEMORY (the index unchanged) when it cannot grow. */
rad_status rad_hash_index_insert(rad_context *ctx, rad_hash_index *index, uint64_t hash, size_t item);
/* Makes the slot found by rad_hash_index_next hold `item` instead (a redefined name). */
void rad_hash_index_replace(rad_hash_index *index, size_t slot, size_t item);
void rad_hash_index_free(rad_context *ctx, rad_hash_index *index);

#endif
