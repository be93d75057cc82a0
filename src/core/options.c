/* options.c - the per-method option bag (rad_options): setting values, and what the methods use
 * to read it (options.h). */
#include "core/options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static rad_option_entry *find(const rad_options *bag, const char *name) {
    for (size_t i = 0; bag && i < bag->count && i < RAD_OPTIONS_MAX; ++i)
        if (strcmp(bag->entries[i].name, name) == 0) return (rad_option_entry *)&bag->entries[i];
    return NULL;
}

rad_status rad_options_set(rad_options *bag, const char *name, const char *value) {
    if (!bag || !name || !value || !*name || strlen(name) >= sizeof bag->entries[0].name ||
        strlen(value) >= sizeof bag->entries[0].value)
        return RAD_ERROR_INVALID_ARGUMENT;
    rad_option_entry *entry = find(bag, name);
    if (!entry) {
        if (bag->count >= RAD_OPTIONS_MAX) return RAD_ERROR_INVALID_ARGUMENT;
        entry = &bag->entries[bag->count++];
        strcpy(entry->name, name);
    }
    strcpy(entry->value, value);
    return RAD_OK;
}

rad_status rad_options_set_number(rad_options *bag, const char *name, double value) {
    char text[sizeof bag->entries[0].value];
    snprintf(text, sizeof text, "%.17g", value);
    return rad_options_set(bag, name, text);
}

const char *rad_options_get(const rad_options *bag, const char *name) {
    const rad_option_entry *entry = name ? find(bag, name) : NULL;
    return entry ? entry->value : NULL;
}

/* The value as a finite number; nonzero on success. */
static int parse_number(const char *text, double *out) {
    char *end;
    double value = strtod(text, &end);
    if (end == text || *end || !isfinite(value)) return 0;
    *out = value;
    return 1;
}

rad_status rad_options_check(rad_context *ctx, const rad_options *bag,
                             const rad_method_option *registered, size_t count, const char *kind,
                             const char *method) {
    for (size_t i = 0; bag && i < bag->count && i < RAD_OPTIONS_MAX; ++i) {
        const rad_option_entry *entry = &bag->entries[i];
        int known = 0;
        for (size_t k = 0; k < count && !known; ++k) known = strcmp(registered[k].name, entry->name) == 0;
        if (!known) {
            char names[256] = "";
            size_t used = 0;
            for (size_t k = 0; k < count && used < sizeof names; ++k)
                used += (size_t)snprintf(names + used, sizeof names - used, "%s%s",
                                         k ? ", " : "", registered[k].name);
            if (count)
                return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                                "%s %s has no option '%s' (its options: %s)", kind, method,
                                entry->name, names);
            return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                            "%s %s has no option '%s' (it has no options)", kind, method,
                            entry->name);
        }
        double value;
        if (!parse_number(entry->value, &value))
            return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                            "%s %s: option '%s' must be a number, not '%s'", kind, method,
                            entry->name, entry->value);
    }
    return RAD_OK;
}

double rad_options_number(const rad_options *bag, const char *name, double fallback) {
    const char *text = rad_options_get(bag, name);
    double value;
    return text && parse_number(text, &value) ? value : fallback;
}
