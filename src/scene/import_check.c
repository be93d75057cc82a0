/* import_check.c - checks PLY and binary glTF headers before assimp reads the file (see
 * import_check.h).
 *
 * PLY: the header is lines of text up to "end_header":
 *   ply
 *   format ascii|binary_little_endian|binary_big_endian 1.0
 *   element NAME COUNT
 *   property TYPE NAME | property list COUNT_TYPE ITEM_TYPE NAME
 *   comment ... | obj_info ...
 * Each row of an element takes at least: in binary, the sizes of its scalar properties plus the
 * size of each list's count; in ASCII, two characters per property (a digit and a separator).
 * The rows promised must fit in what follows the header.
 *
 * Binary glTF: a 12-byte header ("glTF", version 2, total length), then chunks of (length,
 * type, data); every length must fit in the file. */
#include "scene/import_check.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define PLY_MAX_HEADER (1 << 20)

/* Bytes of a PLY scalar type, or 0 when unknown. */
static int type_size(const char *type) {
    static const struct {
        const char *name;
        int size;
    } types[] = {{"char", 1},   {"uchar", 1},  {"int8", 1},    {"uint8", 1},   {"short", 2},
                 {"ushort", 2}, {"int16", 2},  {"uint16", 2},  {"int", 4},     {"uint", 4},
                 {"int32", 4},  {"uint32", 4}, {"float", 4},   {"float32", 4}, {"double", 8},
                 {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (strcmp(types[i].name, type) == 0) return types[i].size;
    return 0;
}

static rad_status check_ply(rad_context *ctx, const char *path, FILE *file, double file_size) {
    char line[1024];
    int binary = -1, line_number = 0, ended = 0;
    double header_size = 0, needed = 0, element_count = 0, row_bytes = 0;
    rad_status status = RAD_OK;
    rewind(file);
    while (!status && fgets(line, sizeof line, file)) {
        ++line_number;
        header_size += (double)strlen(line);
        if (header_size > PLY_MAX_HEADER) break;
        char word[64] = "", a[64] = "", b[64] = "", c[64] = "";
        int fields = sscanf(line, "%63s %63s %63s %63s", word, a, b, c);
        if (fields <= 0) continue;
        if (strcasecmp(word, "format") == 0) {
            binary = strcasecmp(a, "ascii") != 0;
        } else if (strcasecmp(word, "element") == 0) {
            needed += element_count * row_bytes;
            char *end;
            element_count = strtod(b, &end);
            row_bytes = 0;
            if (fields < 3 || *end || !(element_count >= 0))
                status = rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: a PLY element needs a name and "
                                  "a count", path, line_number);
        } else if (strcasecmp(word, "property") == 0) {
            int is_list = strcasecmp(a, "list") == 0;
            int size = type_size(is_list ? b : a);
            if (!size || (is_list && !type_size(c)))
                status = rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: unknown PLY property type",
                                  path, line_number);
            row_bytes += binary == 1 ? size : 2;
        } else if (strcasecmp(word, "end_header") == 0) {
            ended = 1;
            break;
        } else if (line_number > 1 && strcasecmp(word, "comment") != 0 &&
                   strcasecmp(word, "obj_info") != 0) {
            /* assimp loops forever on a header line it does not know (fuzz_import timeout) */
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: not a PLY header line (format, "
                              "element, property, comment, obj_info, end_header)", path,
                              line_number);
        }
    }
    if (status) return status;
    if (!ended)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: the PLY header has no end_header line", path);
    needed += element_count * row_bytes;
    if (needed > file_size - header_size)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: the PLY header promises at least %.0f bytes "
                        "of elements, the file has %.0f after the header", path, needed,
                        file_size - header_size);
    return RAD_OK;
}

static uint32_t read_u32(const unsigned char *b) {
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static rad_status check_glb(rad_context *ctx, const char *path, FILE *file, double file_size) {
    unsigned char header[12];
    rewind(file);
    if (fread(header, 1, 12, file) != 12)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: a binary glTF file of %.0f bytes is too short",
                        path, file_size);
    if (read_u32(header + 4) != 2)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: binary glTF version %u (only 2 is read)", path,
                        (unsigned)read_u32(header + 4));
    double total = read_u32(header + 8);
    if (total > file_size)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: the binary glTF header says %.0f bytes, the "
                        "file has %.0f", path, total, file_size);
    double at = 12;
    for (int chunk = 0; at + 8 <= total; ++chunk) {
        unsigned char chunk_header[8];
        if (fseek(file, (long)at, SEEK_SET) != 0 || fread(chunk_header, 1, 8, file) != 8) break;
        double length = read_u32(chunk_header);
        if (at + 8 + length > total)
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s: binary glTF chunk %d claims %.0f bytes, "
                            "only %.0f are left", path, chunk, length, total - at - 8);
        at += 8 + length;
    }
    return RAD_OK;
}

rad_status rad_import_check(rad_context *ctx, const char *path) {
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    char magic[4] = {0};
    size_t got = fread(magic, 1, 4, file);
    rad_status status = RAD_OK;
    /* assimp takes any file starting "ply" in any case as PLY ("ply," and "pLy" too, and its
     * keywords in any case), so check every one that way (found by fuzz_import). */
    int ply = got >= 3 && strncasecmp(magic, "ply", 3) == 0;
    int glb = got == 4 && memcmp(magic, "glTF", 4) == 0;
    if ((ply || glb) && fseek(file, 0, SEEK_END) == 0) {
        double file_size = (double)ftell(file);
        status = ply ? check_ply(ctx, path, file, file_size) : check_glb(ctx, path, file, file_size);
    }
    fclose(file);
    return status;
}
