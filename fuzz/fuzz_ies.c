/* fuzz_ies.c - libFuzzer target for the IES LM-63 reader (src/light/ies.c): whatever the text,
 * parsing gives a profile whose angles ascend within range and whose candela are finite and
 * >= 0, and whose lookups in every direction are finite, or one error line naming file:line, in
 * bounded time and memory. */
#include "light/lights.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    rad_context_options context_options = {.threads = 1, .max_memory = 64u << 20};
    rad_context *ctx = NULL;
    if (rad_context_create(&context_options, &ctx)) return 0;
    rad_ies_profile *p = NULL;
    rad_status status = rad_ies_parse(ctx, (const char *)data, size, "fuzz.ies", &p);
    if (status == RAD_OK) {
        if (!p || p->vertical_count < 1 || p->horizontal_count < 1) abort();
        for (size_t i = 0; i < p->vertical_count; ++i)
            if (p->vertical[i] < 0 || p->vertical[i] > 180 ||
                (i && !(p->vertical[i] > p->vertical[i - 1])))
                abort();
        for (size_t i = 0; i < p->horizontal_count; ++i)
            if (p->horizontal[i] < 0 || p->horizontal[i] > 360 ||
                (i && !(p->horizontal[i] > p->horizontal[i - 1])))
                abort();
        for (size_t i = 0; i < p->vertical_count * p->horizontal_count; ++i)
            if (!(p->candela[i] >= 0 && isfinite(p->candela[i]))) abort();
        for (int v = -10; v <= 190; v += 5)
            for (int h = -30; h <= 400; h += 7) {
                double candela = rad_ies_candela(p, v, h);
                if (!(candela >= 0 && isfinite(candela))) abort();
            }
    } else {
        const char *message = rad_context_error(ctx);
        if (p || strncmp(message, "fuzz.ies:", 9) != 0 || strchr(message, '\n')) abort();
    }
    rad_ies_free(ctx, p);
    rad_context_destroy(ctx);
    return 0;
}
