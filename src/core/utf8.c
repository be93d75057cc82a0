/* utf8.c - how long the UTF-8 character at a point of a string is (rad_utf8_char_length), so
 * every JSON writer can replace bytes that are not UTF-8 (names read from files, paths) with
 * U+FFFD instead of writing invalid JSON (RFC 8259, section 8.1).
 *
 * Well-formed sequences are those of Unicode's table 3-7: no overlong forms, no surrogates
 * (U+D800..U+DFFF), nothing past U+10FFFF. */
#include "radiosity.h"

int rad_utf8_char_length(const char *text) {
    const unsigned char *s = (const unsigned char *)text;
    if (!s || !s[0]) return 0;
    if (s[0] < 0x80) return 1;
    int length;
    unsigned char low = 0x80, high = 0xBF; /* the range of the second byte */
    if (s[0] >= 0xC2 && s[0] <= 0xDF) length = 2;
    else if (s[0] >= 0xE0 && s[0] <= 0xEF) {
        length = 3;
        if (s[0] == 0xE0) low = 0xA0;  /* overlong */
        if (s[0] == 0xED) high = 0x9F; /* surrogates */
    } else if (s[0] >= 0xF0 && s[0] <= 0xF4) {
        length = 4;
        if (s[0] == 0xF0) low = 0x90;  /* overlong */
        if (s[0] == 0xF4) high = 0x8F; /* past U+10FFFF */
    } else
        return 0;
    if (s[1] < low || s[1] > high) return 0;
    for (int i = 2; i < length; ++i)
        if (s[i] < 0x80 || s[i] > 0xBF) return 0;
    return length;
}
