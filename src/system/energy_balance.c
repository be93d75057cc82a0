/* energy_balance.c - where the emitted power of a solution went (include/radiosity.h,
 * rad_energy_balance): a leak in a closed scene shows as escaped power.
 *
 * In a shooting solution each element's radiosity is B = E + rho H, H the light that has
 * arrived from the shots so far, and U of B is still to be shot. Power shot = sum (B - U) A,
 * arrived = sum H A, so escaped = shot - arrived; with absorbed = sum (1 - rho) H A this is
 * emitted - absorbed - unshot. A converged gathering solution satisfies B = E + rho H with H
 * from all of B, the same balance with no unshot power. */
#include "system/system.h"

#include <string.h>

void rad_system_energy_balance(const rad_system *system, rad_energy_balance *out) {
    memset(out, 0, sizeof *out);
    double emitted = 0, escaped = 0;
    for (size_t e = 0; e < system->element_count; ++e) {
        double area = system->area[e];
        int black = 0;
        for (int c = 0; c < 3; ++c) {
            double rho = system->reflectance[e][c];
            double b = system->radiosity[e][c], emission = system->emission[e][c];
            out->emitted[c] += emission * area;
            if (system->unshot) out->unshot[c] += system->unshot[e][c] * area;
            if (rho > 0) out->absorbed[c] += (1 - rho) * (b - emission) / rho * area;
            else black = 1;
        }
        if (black) out->black_area += area;
    }
    for (int c = 0; c < 3; ++c) {
        out->escaped[c] = out->emitted[c] - out->absorbed[c] - out->unshot[c];
        emitted += out->emitted[c];
        escaped += out->escaped[c];
    }
    out->escaped_fraction = emitted > 0 ? escaped / emitted : 0;
}
