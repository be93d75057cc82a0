/* json.h - the little JSON the tool prints: strings escaped, numbers round-trip exact. */
#ifndef RAD_CLI_JSON_H
#define RAD_CLI_JSON_H

#include <stdio.h>

void json_string(FILE *out, const char *text);
void json_number(FILE *out, double value);
void json_rgb(FILE *out, const double rgb[3]);

#endif
