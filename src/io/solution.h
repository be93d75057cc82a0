/* solution.h - solution files: a system's radiosity and unshot radiosity per element, saved so
 * that a run can stop and go on later, or be rendered without solving again
 * (docs/formats.md, "Solution files"). The public functions are rad_system_save_solution and
 * rad_system_load_solution; this header exposes the fingerprints for tests. */
#ifndef RAD_IO_SOLUTION_H
#define RAD_IO_SOLUTION_H

#include "system/system.h"

#include <stdint.h>

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

#endif
