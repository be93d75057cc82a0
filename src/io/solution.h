/* solution.h - solution files: a system's radiosity and unshot radiosity per element, saved so
 * that a run can stop and go on later, or be rendered without solving again
 * (docs/formats.md, "Solution files"). The public functions are rad_system_save_solution and
 * rad_system_load_solution; this header exposes the fingerprints for tests. */
#ifndef RAD_IO_SOLUTION_H
#define RAD_IO_SOLUTION_H

#include "system/system.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define RAD_SOLUTION_MAGIC "RADSOLN\n"
#define RAD_SOLUTION_VERSION 1u
#define RAD_SOLUTION_HEADER_SIZE 96u
#define RAD_SOLUTION_ELEMENT_SIZE 48u /* radiosity[3], unshot[3], float64 */

/* What a solution belongs to. A file is accepted only by a system whose three fingerprints
 * match the ones it was saved with:
 *   scene         surface names and materials (independent of meshing)
 *   mesh          element and patch structure, element areas and vertex positions (geometry)
 *   form_factors  the provider's method and two of its rows (method, samples, seed) */
typedef struct rad_solution_fingerprint {
    uint64_t scene, mesh, form_factors;
} rad_solution_fingerprint;

rad_status rad_solution_fingerprint_compute(rad_system *system, rad_solution_fingerprint *out);

/* 64-bit FNV-1a, the checksum of the file and the basis of the fingerprints. */
uint64_t rad_fnv1a(uint64_t hash, const void *bytes, size_t count);
#define RAD_FNV1A_START 0xcbf29ce484222325ull

/* Little-endian fields of solution files (solution.c, solution_hier.c). */
static inline void rad_le_put_u64(unsigned char *p, uint64_t v) {
    for (int k = 0; k < 8; ++k) p[k] = (unsigned char)(v >> (8 * k));
}
static inline void rad_le_put_u32(unsigned char *p, uint32_t v) {
    for (int k = 0; k < 4; ++k) p[k] = (unsigned char)(v >> (8 * k));
}
static inline void rad_le_put_u16(unsigned char *p, uint16_t v) {
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
}
static inline void rad_le_put_f64(unsigned char *p, double v) {
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    rad_le_put_u64(p, bits);
}
static inline uint64_t rad_le_get_u64(const unsigned char *p) {
    uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= (uint64_t)p[k] << (8 * k);
    return v;
}
static inline uint32_t rad_le_get_u32(const unsigned char *p) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= (uint32_t)p[k] << (8 * k);
    return v;
}
static inline uint16_t rad_le_get_u16(const unsigned char *p) {
    return (uint16_t)(p[0] | p[1] << 8);
}
static inline double rad_le_get_f64(const unsigned char *p) {
    uint64_t bits = rad_le_get_u64(p);
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

/* The hierarchy's solution files (solution_hier.c, version 3): rad_system_save_solution and
 * rad_system_load_solution hand them over when the system's view is a hierarchy's, or the
 * file's version says so (`file` is open on it, its magic and version checked; it is read as a
 * stream, twice, from its start, so it must be a regular file, not a pipe). */
#define RAD_SOLUTION_HIER_VERSION 3u
rad_status rad_solution_hier_save(rad_system *system, const char *path,
                                  const rad_solution_info *info);
rad_status rad_solution_hier_load(rad_system *system, const char *path, FILE *file,
                                  rad_solution_info *info);

#endif
