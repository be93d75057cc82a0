/* vertex_radiosity.h - the solution where outputs need it: per element for display (with the
 * optional ambient term of progressive refinement) and per mesh vertex for smooth shading and
 * baking. */
#ifndef RAD_SOLVE_VERTEX_RADIOSITY_H
#define RAD_SOLVE_VERTEX_RADIOSITY_H

#include "system/system.h"

/* B_e, plus rho_e * ambient when with_ambient. */
void rad_system_display_radiosity(const rad_system *system, size_t element, int with_ambient,
                                  double out[3]);

/* Area-weighted mean of the display radiosity of the elements around each mesh vertex;
 * out has mesh->vertex_count entries. Geometric systems only. */
rad_status rad_system_vertex_radiosity(const rad_system *system, int with_ambient, rad_rgb *out);

#endif
