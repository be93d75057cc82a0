/* json.c - JSON output helpers. */
#include "json.h"

#include "radiosity.h"

#include <math.h>
#include <stdlib.h>

void json_string(FILE *out, const char *text) {
    fputc('"', out);
    for (const char *s = text ? text : ""; *s;) {
        unsigned char c = (unsigned char)*s;
        int length = rad_utf8_char_length(s);
        if (c == '"' || c == '\\') fprintf(out, "\\%c", c);
        else if (c < 0x20) fprintf(out, "\\u%04x", c);
        else if (!length) fputs("\\ufffd", out); /* not UTF-8: the replacement character */
        else fwrite(s, 1, (size_t)length, out);
        s += length ? length : 1;
    }
    fputc('"', out);
}

void json_number(FILE *out, double value) {
    if (!isfinite(value)) fputs("null", out);
    else {
        /* The shortest form that reads back as the same double. */
        char text[32];
        for (int digits = 15; digits <= 17; ++digits) {
            snprintf(text, sizeof text, "%.*g", digits, value);
            if (strtod(text, NULL) == value) break;
        }
        fputs(text, out);
    }
}

void json_surface_open(FILE *out, size_t index, const char *name, double area) {
    fputs(index ? ",\n  {\"name\": " : "\n  {\"name\": ", out);
    json_string(out, name);
    fputs(", \"area\": ", out);
    json_number(out, area);
}

void json_rgb(FILE *out, const double rgb[3]) {
    fputc('[', out);
    for (int c = 0; c < 3; ++c) {
        if (c) fputs(", ", out);
        json_number(out, rgb[c]);
    }
    fputc(']', out);
}
