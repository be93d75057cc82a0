/* import_check.c - checks PLY and binary glTF headers, and the polylines of OBJ files, before
 * assimp reads the file (see import_check.h).
 *
 * PLY: the header is lines of text up to "end_header":
 *   ply
 *   format ascii|binary_little_endian|binary_big_endian 1.0
 *   element NAME COUNT
 *   property TYPE NAME | property list COUNT_TYPE ITEM_TYPE NAME
 *   comment ... | obj_info ...
 * Each row of an element takes at least: in binary, the sizes of its scalar properties plus the
 * size of each list's count; in ASCII, two characters per property (a digit and a separator).
 * The rows promised must fit in what follows the header. assimp matches "end_header" case by
 * case, so "End_header" is no end to it (it then loops forever): here neither.
 *
 * Binary glTF: a 12-byte header ("glTF", version 2, total length), then chunks of (length,
 * type, data); every length must fit in the file.
 *
 * OBJ: assimp 5.2.5 sizes a mesh's vertex array from its faces, counting two corners per segment
 * of an 'l' polyline, so an 'l' with a single vertex is counted as none but still takes a slot
 * (ObjFileImporter::createVertexArray). Two such lines before a polyline of three vertices
 * shift the copy of that polyline's middle vertex one element past the array: a heap overflow,
 * which glibc reports as "malloc assertion failure" and aborts (found by fuzz_import). So every
 * 'l' needs two vertices, counted the way assimp parses them (ObjFileParser::getFace), and a
 * line continuation '\\' must end in a newline (else assimp searches for that newline past its
 * buffer). The count errs on the safe side: a statement starts after any character assimp ends
 * a line on (CR, LF, NUL, form feed), and only indices written V, V/T, V//N or V/T/N with at
 * most nine digits each count, up to the first token that is written otherwise. */
#include "scene/import_check.h"

#include <ctype.h>
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

/* The layout of the PLY elements, for the ASCII body check: per element its name, row count
 * and its properties in order (1 a scalar, 2 a list). Headers with more are not body-checked. */
#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPERTIES 64
typedef struct ply_element {
    char name[64];
    double rows;
    int property_count;
    unsigned char properties[PLY_MAX_PROPERTIES];
} ply_element;

/* ASCII PLY: assimp reads the values of the rows as one stream of numbers, so a file with fewer
 * rows than its header promises (a vertex count one too high) has its faces read as vertices
 * and faces invented from what follows. Each row is a line: it must hold the values its
 * properties take (a list: its count, then that many), and every promised row must be there. */
static rad_status check_ply_ascii_rows(rad_context *ctx, const char *path, FILE *file,
                                       int header_lines, const ply_element *elements,
                                       int element_count) {
    char line[4096];
    int line_number = header_lines;
    for (int e = 0; e < element_count; ++e) {
        const ply_element *element = &elements[e];
        for (double row = 0; row < element->rows; ++row) {
            char *text = NULL;
            do { /* blank lines between rows are allowed */
                text = fgets(line, sizeof line, file);
                ++line_number;
                /* a row longer than the buffer: the rest is left to assimp */
                if (text && !strchr(line, '\n') && !feof(file)) return RAD_OK;
            } while (text && strspn(line, " \t\r\n") == strlen(line));
            if (!text)
                return rad_fail(ctx, RAD_ERROR_PARSE, "%s: the PLY file ends after %.0f of the "
                                "%.0f '%s' rows its header promises", path, row, element->rows,
                                element->name);
            char *at = line, *end;
            for (int p = 0; p < element->property_count; ++p) {
                double value = strtod(at, &end), items = 0;
                if (end != at && element->properties[p] == 2) items = value >= 0 ? value : 0;
                for (double item = 0; end != at && item < items; ++item) {
                    at = end;
                    strtod(at, &end);
                }
                if (end == at)
                    return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: this '%s' row has fewer "
                                    "values than the header's properties take", path,
                                    line_number, element->name);
                at = end;
            }
        }
    }
    return RAD_OK;
}

static rad_status check_ply(rad_context *ctx, const char *path, FILE *file, double file_size) {
    char line[1024];
    int binary = -1, line_number = 0, ended = 0, layout_count = 0, layout_known = 1;
    double header_size = 0, needed = 0, element_count = 0, row_bytes = 0;
    ply_element layout[PLY_MAX_ELEMENTS];
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
            if (layout_count < PLY_MAX_ELEMENTS) {
                ply_element *element = &layout[layout_count++];
                snprintf(element->name, sizeof element->name, "%s", a);
                element->rows = element_count;
                element->property_count = 0;
            } else
                layout_known = 0;
        } else if (strcasecmp(word, "property") == 0) {
            int is_list = strcasecmp(a, "list") == 0;
            int size = type_size(is_list ? b : a);
            if (!size || (is_list && !type_size(c)))
                status = rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: unknown PLY property type",
                                  path, line_number);
            row_bytes += binary == 1 ? size : 2;
            ply_element *element = layout_count ? &layout[layout_count - 1] : NULL;
            if (element && element->property_count < PLY_MAX_PROPERTIES)
                element->properties[element->property_count++] = (unsigned char)(1 + is_list);
            else
                layout_known = 0;
        } else if (strcmp(word, "end_header") == 0) {
            ended = 1;
            break;
        } else if (strcasecmp(word, "end_header") == 0) {
            /* assimp matches end_header case by case, so it finds no end and loops forever
             * (fuzz_import timeout). Other lines it does not know it skips, as here: Blender
             * 2.47 wrote a free text line ("Created by Blender3D 247 ...") into the header. */
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: '%s' must be written end_header "
                              "(lower case) to end a PLY header", path, line_number, word);
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
    if (binary == 0 && layout_known)
        return check_ply_ascii_rows(ctx, path, file, line_number, layout, layout_count);
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

/* ------------------------------------------------------------------------------------------- */
/* OBJ polylines.                                                                               */

/* Characters on which assimp's OBJ reader ends a line (ParsingUtils.h: IsLineEnd). */
static int obj_line_end(int c) { return c == '\n' || c == '\r' || c == '\0' || c == '\f'; }

/* One index token of an 'l' statement: up to three parts split by '/', each -?[1-9][0-9]{0,8}
 * or (texture and normal) empty. Such a token moves assimp's face reader exactly to its end
 * (it steps by the digits of the value it read), so its vertex is counted once. */
typedef struct obj_token {
    int plain;     /* so far of that form */
    int part;      /* 0 vertex, 1 texture, 2 normal */
    int digits;    /* of the current part */
    int sign;      /* the current part has a '-' */
    int filled[3]; /* which parts hold a number */
} obj_token;

static void obj_token_start(obj_token *t) {
    memset(t, 0, sizeof *t);
    t->plain = 1;
}

/* A part ends: it must be a number, or empty unless it is the vertex. */
static int obj_part_end(obj_token *t) {
    if (t->sign && !t->digits) return 0;
    if (t->part == 0 && !t->digits) return 0;
    t->filled[t->part] = t->digits > 0;
    return 1;
}

static void obj_token_add(obj_token *t, int c) {
    if (!t->plain) return;
    if (c == '/') {
        if (t->part == 2 || !obj_part_end(t)) {
            t->plain = 0;
            return;
        }
        t->part++;
        t->digits = t->sign = 0;
    } else if (c == '-' && !t->digits && !t->sign) {
        t->sign = 1;
    } else if (c >= '0' && c <= '9' && (c != '0' || t->digits) && t->digits < 9) {
        t->digits++;
    } else {
        t->plain = 0;
    }
}

/* 1 when the token counts as a vertex of the statement. */
static int obj_token_end(obj_token *t) { return t->plain && obj_part_end(t); }

/* Could assimp hand `path` to its OBJ reader? A ".obj" name, or contents its OBJ reader
 * claims: assimp 5.2.5 asks each reader in turn (ObjFileImporter::CanRead, whatever the
 * extension), and OBJ's says yes when the first 200 bytes, lower-cased and with NULs removed,
 * hold one of its keywords where the first occurrence has no letter just before it
 * (BaseImporter::SearchFileHeaderForToken). Binary files (.max, .usdc, .m3d) seldom do, and
 * then get assimp's "not a format it can read" rather than an OBJ syntax error. */
static int obj_reader_possible(const char *path, FILE *file) {
    size_t length = strlen(path);
    if (length >= 4 && strcasecmp(path + length - 4, ".obj") == 0) return 1;
    static const char *const keywords[] = {"mtllib", "usemtl", "v ", "vt ", "vn ",
                                           "o ",     "g ",     "s ", "f "};
    char head[201];
    rewind(file);
    size_t got = fread(head, 1, 200, file), kept = 0;
    for (size_t i = 0; i < got; ++i)
        if (head[i]) head[kept++] = (char)tolower((unsigned char)head[i]);
    head[kept] = '\0';
    for (size_t k = 0; k < sizeof keywords / sizeof keywords[0]; ++k) {
        const char *at = strstr(head, keywords[k]);
        if (at && (at == head || !isalpha((unsigned char)at[-1]))) return 1;
    }
    return 0;
}

/* Binary data in the first 200 bytes: a NUL or a control character other than tab, CR, LF and
 * form feed. */
static int binary_start(FILE *file) {
    unsigned char head[200];
    rewind(file);
    size_t got = fread(head, 1, sizeof head, file);
    for (size_t i = 0; i < got; ++i)
        if (head[i] < 0x20 && head[i] != '\t' && head[i] != '\r' && head[i] != '\n' &&
            head[i] != '\f')
            return 1;
    return 0;
}

static rad_status polyline_error(rad_context *ctx, const char *path, long line,
                                 const char *keyword) {
    if (strcmp(keyword, "l") == 0)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%ld: a polyline ('l') needs at least two "
                        "vertex indices, written V, V/T, V//N or V/T/N", path, line);
    return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%ld: assimp reads '%s' as a polyline ('l'), which "
                    "needs at least two vertex indices", path, line, keyword);
}

static rad_status check_obj(rad_context *ctx, const char *path, FILE *file) {
    enum { AT_START, AFTER_V, SKIP, KEYWORD, INDICES } state = AT_START;
    unsigned char buffer[1 << 16];
    char keyword[16] = "";
    size_t keyword_length = 0;
    long line_number = 1, statement_line = 1, vertices = 0;
    int before = -1, previous = -1, texcoords_seen = 0, counting = 0, in_token = 0;
    obj_token token;
    /* A UTF-8 byte-order mark: assimp reads it as part of the first statement, which it then
     * does not know and skips, so a first line "mtllib room.mtl" loses every material (and the
     * lamp's emission) and a first "v" shifts every index. A comment or blank line is safe. */
    unsigned char start[4] = {0};
    rewind(file);
    size_t start_length = fread(start, 1, sizeof start, file);
    if (start_length >= 4 && memcmp(start, "\xef\xbb\xbf", 3) == 0 && start[3] != '#' &&
        !obj_line_end(start[3]))
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:1: a UTF-8 byte-order mark before the first "
                        "statement hides it from assimp; remove the mark (the first 3 bytes) or "
                        "start the file with a comment", path);
    rewind(file);
    for (size_t got = sizeof buffer; got == sizeof buffer;) {
        got = fread(buffer, 1, sizeof buffer, file);
        if (got < sizeof buffer && ferror(file))
            return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
        for (size_t i = 0; i <= got; ++i) {
            if (i == got && got == sizeof buffer) break; /* more to read */
            int c = i < got ? buffer[i] : EOF;
            /* A continuation: assimp skips from '\\' to the next '\n', so only "\\\n" and
             * "\\\r\n" stay inside its buffer. */
            if ((previous == '\\' && (c == EOF || c == '\0' || c == '\f')) ||
                (before == '\\' && previous == '\r' && c != '\n'))
                return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%ld: a line continuation ('\\') must "
                                "be followed by a newline", path, line_number - (previous == '\r'));
            if (c == EOF || obj_line_end(c)) {
                if (state == KEYWORD || state == INDICES) {
                    if (in_token && counting) vertices += obj_token_end(&token);
                    if (vertices < 2) return polyline_error(ctx, path, statement_line, keyword);
                }
                if (c == EOF) return RAD_OK;
                if (c == '\n' ? previous != '\r' : c == '\r') ++line_number;
                state = AT_START;
            } else if (state == AT_START) {
                statement_line = line_number;
                state = c == 'l' ? KEYWORD : c == 'v' ? AFTER_V : SKIP;
                keyword[0] = (char)c, keyword[1] = '\0', keyword_length = 1;
                vertices = 0, counting = 1, in_token = 0;
            } else if (state == AFTER_V) {
                if (c == 't') texcoords_seen = 1;
                state = SKIP;
            } else if (state == KEYWORD) {
                if (c == ' ' || c == '\t') {
                    state = INDICES;
                } else if (keyword_length + 1 < sizeof keyword && c >= 0x20 && c < 0x7f) {
                    keyword[keyword_length++] = (char)c;
                    keyword[keyword_length] = '\0';
                }
            } else if (state == INDICES) {
                if (c == ' ' || c == '\t') {
                    if (in_token && counting) {
                        int counted = obj_token_end(&token);
                        vertices += counted;
                        /* V/T/N before any 'vt': assimp takes T for N, finds a fourth part in
                         * N and skips the rest of the line. */
                        if (!counted || (token.filled[1] && token.filled[2] && !texcoords_seen))
                            counting = 0;
                    }
                    in_token = 0;
                } else {
                    if (!in_token) obj_token_start(&token), in_token = 1;
                    obj_token_add(&token, c);
                }
            }
            before = previous, previous = c;
        }
    }
    return RAD_OK; /* not reached: the EOF step returns */
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
    } else if (!ply && !glb && obj_reader_possible(path, file)) {
        size_t length = strlen(path);
        int obj_name = length >= 4 && strcasecmp(path + length - 4, ".obj") == 0;
        /* A binary file of another format (a .max, .usdc or .m3d that no reader in this assimp
         * claims) that assimp would take for OBJ text: say what it is, not an OBJ syntax error. */
        if (!obj_name && binary_start(file))
            status = rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: not a scene format assimp can "
                              "read (binary data that only its OBJ reader would take, as text)",
                              path);
        else
            status = check_obj(ctx, path, file);
    }
    fclose(file);
    return status;
}
