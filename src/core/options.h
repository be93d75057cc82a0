/* options.h - reading a per-method option bag (rad_options, include/radiosity.h): the names a
 * method registered, checked against the bag, and their values as numbers. */
#ifndef RAD_CORE_OPTIONS_H
#define RAD_CORE_OPTIONS_H

#include "core/context.h"

/* RAD_OK when every name in `bag` (may be NULL) is one of the `count` registered options;
 * otherwise an error "<kind> <method> has no option 'x' (its options: a, b)" or "(it has no
 * options)". Also refuses values that are not finite numbers, naming the option. */
rad_status rad_options_check(rad_context *ctx, const rad_options *bag,
                             const rad_method_option *registered, size_t count, const char *kind,
                             const char *method);

/* The number `name` is set to in `bag` (checked by rad_options_check first), or `fallback`
 * when the bag is NULL or does not set it. */
double rad_options_number(const rad_options *bag, const char *name, double fallback);

#endif
