/* json.h - the little JSON the tool prints: strings escaped, numbers round-trip exact. */
#ifndef RAD_CLI_JSON_H
#define RAD_CLI_JSON_H

#include <stdio.h>

void json_string(FILE *out, const char *text);
void json_number(FILE *out, double value);
void json_rgb(FILE *out, const double rgb[3]);

/* The start of a surface's object in a list: separator, then {"name": ..., "area": ...
 * (the caller adds its own fields and the closing brace). */
void json_surface_open(FILE *out, size_t index, const char *name, double area);

#endif
