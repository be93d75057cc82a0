/* image_exr.c - OpenEXR images (see image_exr.h) through OpenEXR's C API, OpenEXRCore 3.1.
 *
 * Writing: one scanline part, channels B, G, R (EXR keeps them sorted by name), ZIP compressed
 * (lossless), data and display window 0..width-1 x 0..height-1, linear radiance as it is (no
 * exposure, no tone curve). The encoder reads our interleaved RGB floats directly (pixel stride
 * 12 bytes) and converts to half itself when asked. Bytes go through a write callback into the
 * FILE the caller opened, so the atomic temporary-file-and-rename of image.c still applies.
 *
 * Reading: the whole file is read into memory (bounded by its length) and handed to OpenEXR
 * through read and size callbacks; every chunk is decoded straight into the image as floats.
 * OpenEXR's own error text is kept (through its error handler) and becomes the one line. */
#include "image/image_exr.h"

#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <OpenEXR/openexr.h>

/* Largest side accepted, as in image.c. */
#define RAD_EXR_MAX_SIDE 65536

/* What the callbacks see: the bytes (reading) or the FILE (writing), and the first error
 * message OpenEXR reported. */
typedef struct exr_stream {
    const unsigned char *bytes;
    uint64_t size;
    FILE *file;
    int write_failed;
    char message[256];
} exr_stream;

static void keep_message(exr_const_context_t exr, exr_result_t code, const char *message) {
    void *user = NULL;
    if (exr_get_user_data(exr, &user) != EXR_ERR_SUCCESS || !user) return;
    exr_stream *stream = user;
    if (stream->message[0]) return; /* the first error names the cause; later ones follow from it */
    snprintf(stream->message, sizeof stream->message, "%s",
             message ? message : exr_get_default_error_message(code));
}

static const char *message_of(const exr_stream *stream, exr_result_t code) {
    return stream->message[0] ? stream->message : exr_get_default_error_message(code);
}

static int64_t read_bytes(exr_const_context_t exr, void *user, void *buffer, uint64_t size,
                          uint64_t offset, exr_stream_error_func_ptr_t error) {
    (void)exr;
    (void)error;
    const exr_stream *stream = user;
    if (offset >= stream->size) return 0;
    uint64_t available = stream->size - offset;
    uint64_t count = size < available ? size : available;
    memcpy(buffer, stream->bytes + offset, (size_t)count);
    return (int64_t)count;
}

static int64_t size_of_bytes(exr_const_context_t exr, void *user) {
    (void)exr;
    return (int64_t)((const exr_stream *)user)->size;
}

static int64_t write_bytes(exr_const_context_t exr, void *user, const void *buffer, uint64_t size,
                           uint64_t offset, exr_stream_error_func_ptr_t error) {
    (void)exr;
    (void)error;
    exr_stream *stream = user;
    if (offset > (uint64_t)LONG_MAX || fseek(stream->file, (long)offset, SEEK_SET) != 0 ||
        fwrite(buffer, 1, (size_t)size, stream->file) != size) {
        stream->write_failed = 1;
        return -1;
    }
    return (int64_t)size;
}

static exr_context_initializer_t initializer(exr_stream *stream) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keep_message;
    init.user_data = stream;
    init.max_image_width = RAD_EXR_MAX_SIDE;
    init.max_image_height = RAD_EXR_MAX_SIDE;
    init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
    return init;
}

/* ---- writing ------------------------------------------------------------------------------ */

rad_status rad_exr_write(const rad_image *image, FILE *file, const char *path, int half) {
    rad_context *ctx = image->ctx;
    exr_stream stream = {0};
    stream.file = file;
    exr_context_initializer_t init = initializer(&stream);
    init.write_fn = write_bytes;
    init.flags = 0;
    exr_context_t exr = NULL;
    exr_encode_pipeline_t encoder = {0};
    int encoder_ready = 0;
    exr_result_t result = exr_start_write(&exr, path, EXR_WRITE_FILE_DIRECTLY, &init);
    int part = 0;
    if (result == EXR_ERR_SUCCESS)
        result = exr_add_part(exr, "radiosity", EXR_STORAGE_SCANLINE, &part);
    if (result == EXR_ERR_SUCCESS)
        result = exr_initialize_required_attr_simple(exr, part, image->width, image->height,
                                                     EXR_COMPRESSION_ZIP);
    static const char *const names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3 && result == EXR_ERR_SUCCESS; ++c)
        result = exr_add_channel(exr, part, names[c], half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                                 EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (result == EXR_ERR_SUCCESS) result = exr_write_header(exr);
    int lines_per_chunk = 1;
    if (result == EXR_ERR_SUCCESS) result = exr_get_scanlines_per_chunk(exr, part, &lines_per_chunk);
    size_t row_bytes = (size_t)image->width * 3 * sizeof(float);
    for (int y = 0; y < image->height && result == EXR_ERR_SUCCESS; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        result = exr_write_scanline_chunk_info(exr, part, y, &chunk);
        if (result != EXR_ERR_SUCCESS) break;
        result = encoder_ready ? exr_encoding_update(exr, part, &chunk, &encoder)
                               : exr_encoding_initialize(exr, part, &chunk, &encoder);
        if (result != EXR_ERR_SUCCESS) break;
        for (int i = 0; i < encoder.channel_count; ++i) {
            exr_coding_channel_info_t *channel = &encoder.channels[i];
            const char *name = channel->channel_name;
            int c = name[0] == 'R' ? 0 : name[0] == 'G' ? 1 : 2;
            channel->user_pixel_stride = 3 * sizeof(float);
            channel->user_line_stride = (int32_t)row_bytes;
            channel->user_bytes_per_element = sizeof(float);
            channel->user_data_type = EXR_PIXEL_FLOAT;
            channel->encode_from_ptr =
                (const uint8_t *)(image->pixels + (size_t)chunk.start_y * image->width * 3 + c);
        }
        if (!encoder_ready) {
            result = exr_encoding_choose_default_routines(exr, part, &encoder);
            encoder_ready = 1;
            if (result != EXR_ERR_SUCCESS) break;
        }
        result = exr_encoding_run(exr, part, &encoder);
    }
    if (encoder_ready) exr_encoding_destroy(exr, &encoder);
    exr_result_t finished = exr_finish(&exr);
    if (result == EXR_ERR_SUCCESS) result = finished;
    if (stream.write_failed)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
    if (result != EXR_ERR_SUCCESS)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot encode the EXR image: %s", path,
                        message_of(&stream, result));
    return RAD_OK;
}

/* ---- reading ------------------------------------------------------------------------------ */

/* Index 0..2 of the default layer's R, G or B channel, 3 for Y, -1 for any other channel
 * (alpha, depth, other layers such as "diffuse.R": skipped). */
static int channel_slot(const char *name) {
    if (strcmp(name, "R") == 0) return 0;
    if (strcmp(name, "G") == 0) return 1;
    if (strcmp(name, "B") == 0) return 2;
    if (strcmp(name, "Y") == 0) return 3;
    return -1;
}

static rad_status decode(rad_context *ctx, const char *path, exr_context_t exr, exr_stream *stream,
                         rad_image **out) {
#define EXR_FAIL(status_, ...) do { status = rad_fail(ctx, status_, __VA_ARGS__); goto done; } while (0)
#define EXR_CHECK(call_)                                                                        \
    do {                                                                                        \
        exr_result_t r_ = (call_);                                                              \
        if (r_ != EXR_ERR_SUCCESS)                                                              \
            EXR_FAIL(RAD_ERROR_PARSE, "%s: damaged EXR file: %s", path, message_of(stream, r_)); \
    } while (0)
    rad_status status = RAD_OK;
    rad_image *image = NULL;
    exr_decode_pipeline_t decoder = {0};
    int decoder_ready = 0;
    float *skipped = NULL; /* where the channels not kept are decoded to (below) */

    exr_storage_t storage;
    EXR_CHECK(exr_get_storage(exr, 0, &storage));
    if (storage != EXR_STORAGE_SCANLINE)
        EXR_FAIL(RAD_ERROR_UNSUPPORTED, "%s: only scanline EXR images are read (this one is %s)",
                 path, storage == EXR_STORAGE_TILED ? "tiled" : "deep");
    exr_attr_box2i_t window;
    EXR_CHECK(exr_get_data_window(exr, 0, &window));
    int64_t width = (int64_t)window.max.x - window.min.x + 1;
    int64_t height = (int64_t)window.max.y - window.min.y + 1;
    if (width < 1 || height < 1 || width > RAD_EXR_MAX_SIDE || height > RAD_EXR_MAX_SIDE)
        EXR_FAIL(RAD_ERROR_PARSE, "%s: EXR data window %lldx%lld out of range (1 to %d per side)",
                 path, (long long)width, (long long)height, RAD_EXR_MAX_SIDE);
    const exr_attr_chlist_t *channels = NULL;
    EXR_CHECK(exr_get_channels(exr, 0, &channels));
    int present[4] = {0};
    for (int i = 0; channels && i < channels->num_channels; ++i) {
        const exr_attr_chlist_entry_t *entry = &channels->entries[i];
        int slot = channel_slot(entry->name.str ? entry->name.str : "");
        if (slot < 0) continue;
        if (entry->x_sampling != 1 || entry->y_sampling != 1)
            EXR_FAIL(RAD_ERROR_UNSUPPORTED, "%s: subsampled EXR channel '%s' is not supported",
                     path, entry->name.str);
        present[slot] = 1;
    }
    int gray = !(present[0] && present[1] && present[2]);
    if (gray && !present[3])
        EXR_FAIL(RAD_ERROR_UNSUPPORTED, "%s: EXR image has neither R, G, B nor Y channels", path);
    if ((status = rad_image_new(ctx, (int)width, (int)height, &image))) goto done;

    int lines_per_chunk = 1;
    EXR_CHECK(exr_get_scanlines_per_chunk(exr, 0, &lines_per_chunk));
    if (lines_per_chunk < 1) EXR_FAIL(RAD_ERROR_PARSE, "%s: damaged EXR file (chunk size)", path);
    size_t row_bytes = (size_t)width * 3 * sizeof(float);
    /* The channels not kept (alpha, other layers, the unused one of Y and RGB) are decoded into
     * one scratch chunk and dropped. A NULL destination, which OpenEXR documents as "skip",
     * made OpenEXR 3.1's decoder write through NULL on a ZIP chunk stored uncompressed with one
     * kept half channel of three (found by fuzz_image; fuzz/regressions/image keeps the input). */
    skipped = rad_alloc(ctx, (size_t)width * (size_t)lines_per_chunk, sizeof *skipped);
    if (!skipped) EXR_FAIL(RAD_ERROR_NO_MEMORY, "%s: no memory for an EXR chunk", path);
    for (int64_t y = window.min.y; y <= window.max.y; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        EXR_CHECK(exr_read_scanline_chunk_info(exr, 0, (int)y, &chunk));
        if (chunk.start_y < window.min.y || (int64_t)chunk.start_y + chunk.height - 1 > window.max.y ||
            chunk.height > lines_per_chunk)
            EXR_FAIL(RAD_ERROR_PARSE, "%s: damaged EXR file (chunk at line %d)", path, chunk.start_y);
        EXR_CHECK(decoder_ready ? exr_decoding_update(exr, 0, &chunk, &decoder)
                                : exr_decoding_initialize(exr, 0, &chunk, &decoder));
        float *first_row = image->pixels + (size_t)(chunk.start_y - window.min.y) * (size_t)width * 3;
        for (int i = 0; i < decoder.channel_count; ++i) {
            exr_coding_channel_info_t *channel = &decoder.channels[i];
            int slot = channel_slot(channel->channel_name ? channel->channel_name : "");
            if (slot == 3) slot = gray ? 0 : -1; /* Y only for a gray image, into red first */
            int kept = slot >= 0 && channel->height > 0;
            channel->user_pixel_stride = kept ? 3 * sizeof(float) : sizeof(float);
            channel->user_line_stride = (int32_t)(kept ? row_bytes : (size_t)width * sizeof(float));
            channel->user_bytes_per_element = sizeof(float);
            channel->user_data_type = EXR_PIXEL_FLOAT;
            channel->decode_to_ptr = kept ? (uint8_t *)(first_row + slot) : (uint8_t *)skipped;
        }
        if (!decoder_ready) {
            EXR_CHECK(exr_decoding_choose_default_routines(exr, 0, &decoder));
            decoder_ready = 1;
        }
        EXR_CHECK(exr_decoding_run(exr, 0, &decoder));
    }
    if (gray) { /* copy Y from red into green and blue */
        size_t count = (size_t)width * (size_t)height;
        for (size_t i = 0; i < count; ++i)
            image->pixels[3 * i + 1] = image->pixels[3 * i + 2] = image->pixels[3 * i];
    }
done:
#undef EXR_CHECK
#undef EXR_FAIL
    if (decoder_ready || decoder.channels) exr_decoding_destroy(exr, &decoder);
    rad_free(ctx, skipped);
    if (status) {
        rad_image_free(image);
        return status;
    }
    *out = image;
    return RAD_OK;
}

rad_status rad_exr_read(rad_context *ctx, const char *path, rad_image **out) {
    *out = NULL;
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    long length = -1;
    if (fseek(file, 0, SEEK_END) == 0) length = ftell(file);
    if (length < 0 || fseek(file, 0, SEEK_SET) != 0) {
        fclose(file);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read", path);
    }
    rad_status status = rad_check_budget(ctx, (double)length, "the EXR file");
    unsigned char *bytes = status ? NULL : rad_alloc(ctx, (size_t)length + 1, 1);
    if (!status && !bytes) status = RAD_ERROR_NO_MEMORY;
    size_t size = bytes ? fread(bytes, 1, (size_t)length, file) : 0;
    fclose(file);
    if (status) return status;

    exr_stream stream = {0};
    stream.bytes = bytes;
    stream.size = size;
    exr_context_initializer_t init = initializer(&stream);
    init.read_fn = read_bytes;
    init.size_fn = size_of_bytes;
    exr_context_t exr = NULL;
    exr_result_t result = exr_start_read(&exr, path, &init);
    int parts = 0;
    if (result == EXR_ERR_SUCCESS) result = exr_get_count(exr, &parts);
    if (result != EXR_ERR_SUCCESS || parts < 1)
        status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a readable EXR file: %s", path,
                          result != EXR_ERR_SUCCESS ? message_of(&stream, result) : "no parts");
    else
        status = decode(ctx, path, exr, &stream, out);
    exr_finish(&exr);
    rad_free(ctx, bytes);
    return status;
}
