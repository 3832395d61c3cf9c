/* OpenEXR Core C API: float images with named channels (see exr_io.h). */
#include "sparselens/exr_io.h"

#include <openexr.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/outfile.h"

/* The library prints to stderr by default; errors are reported through lens_err. */
static void quiet(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt, (void)code, (void)msg;
}

static int fail(lens_err *err, const char *path, const char *what, exr_result_t rv)
{
    lens_errf(err, path, 0, "%s: %s", what, exr_get_default_error_message(rv));
    return -1;
}

static int find_name(int n, const char *const *names, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

/* OpenEXR Core 3.1 stores zlib's output whenever it is not longer than the chunk, but
 * its reader takes a chunk of exactly the unpacked size as stored raw: a chunk that
 * compresses to exactly its own size is written compressed and read back as garbage
 * (16 rows of +-1e34 and NaN; fixed upstream in OpenEXR 3.4, issue #2306). The spec's
 * rule is "whichever is smaller"; this hook, run by exr_encoding_run between compressing
 * and writing, stores such a chunk raw. */
static exr_result_t store_raw_unless_smaller(exr_encode_pipeline_t *enc)
{
    if (enc->compressed_buffer && enc->compressed_buffer != enc->packed_buffer &&
        enc->compressed_bytes >= enc->packed_bytes && enc->compressed_alloc_size >= enc->packed_bytes) {
        memcpy(enc->compressed_buffer, enc->packed_buffer, enc->packed_bytes);
        enc->compressed_bytes = enc->packed_bytes;
    }
    return EXR_ERR_SUCCESS;
}

static int write_body(exr_context_t f, int width, int height, int nch, const char *const *names,
                      const float *const *planes, const char *path, lens_err *err)
{
    int part = 0;
    exr_result_t rv = exr_add_part(f, "image", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(f, part, width, height, EXR_COMPRESSION_ZIP);
    for (int c = 0; c < nch && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(f, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(f);
    if (rv != EXR_ERR_SUCCESS)
        return fail(err, path, "cannot write EXR header", rv);
    int32_t lines = 1;
    exr_get_scanlines_per_chunk(f, part, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < height && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(f, part, y, &ci);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_encoding_update(f, part, &ci, &enc)
                     : exr_encoding_initialize(f, part, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        /* The pipeline lists channels in the file's (sorted) order: match by name. */
        for (int k = 0; k < enc.channel_count; k++) {
            exr_coding_channel_info_t *ch = &enc.channels[k];
            int c = find_name(nch, names, ch->channel_name);
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)sizeof(float) * width;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->encode_from_ptr = (const uint8_t *)(planes[c] + (size_t)y * (size_t)width);
        }
        if (!started) {
            rv = exr_encoding_choose_default_routines(f, part, &enc);
            started = 1;
        }
        enc.yield_until_ready_fn = store_raw_unless_smaller;
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(f, part, &enc);
    }
    if (started)
        exr_encoding_destroy(f, &enc);
    if (rv != EXR_ERR_SUCCESS)
        return fail(err, path, "cannot write EXR data", rv);
    return 0;
}

/* Reads the written file back and compares it bit for bit with what was meant: a
 * compressor's bug must not leave a corrupt picture behind that looks like a result. */
static int verify_written(const char *tmp, const char *path, int width, int height, int nch,
                          const char *const *names, const float *const *planes, lens_err *err)
{
    exr_image back;
    if (exr_read_float(tmp, &back, err) != 0) {
        lens_errf(err, path, 0, "the EXR file written does not read back; not written");
        return -1;
    }
    int bad = back.width != width || back.height != height || back.nchannels != nch;
    size_t n = (size_t)width * (size_t)height;
    for (int c = 0; c < nch && !bad; c++) {
        const float *q = exr_image_channel(&back, names[c]);
        bad = !q || memcmp(q, planes[c], n * sizeof(float)) != 0;
    }
    exr_image_free(&back);
    if (bad)
        lens_errf(err, path, 0, "the EXR file written reads back different from the image "
                                "(an OpenEXR encoder fault); not written");
    return bad ? -1 : 0;
}

int exr_write_float(const char *path, int width, int height, int nchannels,
                    const char *const *names, const float *const *planes, lens_err *err)
{
    if (width <= 0 || height <= 0 || nchannels <= 0) {
        lens_errf(err, path, 0, "EXR image must have a positive size and channels");
        return -1;
    }
    for (int c = 0; c < nchannels; c++)
        if (!names[c] || !*names[c] || find_name(c, names, names[c]) >= 0) {
            lens_errf(err, path, 0, "EXR channel names must be distinct and non-empty");
            return -1;
        }
    char tmp[4096];
    if (outfile_tmp_path(path, tmp, sizeof tmp) != 0) {
        lens_errf(err, path, 0, "cannot make a temporary file name");
        return -1;
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    exr_context_t f = NULL;
    exr_result_t rv = exr_start_write(&f, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        outfile_discard_path(tmp);
        return fail(err, path, "cannot create EXR file", rv);
    }
    int bad = write_body(f, width, height, nchannels, names, planes, path, err);
    rv = exr_finish(&f);
    if (!bad && rv != EXR_ERR_SUCCESS)
        bad = fail(err, path, "cannot finish EXR file", rv);
    if (!bad)
        bad = verify_written(tmp, path, width, height, nchannels, names, planes, err);
    if (bad) {
        outfile_discard_path(tmp);
        return -1;
    }
    return outfile_commit_path(tmp, path, err);
}

void exr_image_free(exr_image *img)
{
    for (int c = 0; c < img->nchannels; c++) {
        if (img->names)
            free(img->names[c]);
        if (img->planes)
            free(img->planes[c]);
    }
    free(img->names);
    free(img->planes);
    memset(img, 0, sizeof *img);
}

const float *exr_image_channel(const exr_image *img, const char *name)
{
    for (int c = 0; c < img->nchannels; c++)
        if (strcmp(img->names[c], name) == 0)
            return img->planes[c];
    return NULL;
}

static int read_body(exr_context_t f, exr_image *img, const char *path, lens_err *err)
{
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    exr_storage_t storage;
    exr_result_t rv = exr_get_storage(f, 0, &storage);
    if (rv == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE) {
        lens_errf(err, path, 0, "only scanline EXR files are supported");
        return -1;
    }
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_data_window(f, 0, &dw);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_channels(f, 0, &chl);
    if (rv != EXR_ERR_SUCCESS)
        return fail(err, path, "cannot read EXR header", rv);
    long w = (long)dw.max.x - dw.min.x + 1, h = (long)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > 100000000L || chl->num_channels <= 0) {
        lens_errf(err, path, 0, "EXR image is empty or too large");
        return -1;
    }
    for (int c = 0; c < chl->num_channels; c++)
        if (chl->entries[c].x_sampling != 1 || chl->entries[c].y_sampling != 1) {
            lens_errf(err, path, 0, "subsampled EXR channels are not supported");
            return -1;
        }
    img->width = (int)w;
    img->height = (int)h;
    img->names = calloc((size_t)chl->num_channels, sizeof *img->names);
    img->planes = calloc((size_t)chl->num_channels, sizeof *img->planes);
    if (!img->names || !img->planes) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    img->nchannels = chl->num_channels;
    for (int c = 0; c < img->nchannels; c++) {
        img->names[c] = strdup(chl->entries[c].name.str);
        img->planes[c] = calloc((size_t)(w * h), sizeof(float));
        if (!img->names[c] || !img->planes[c]) {
            lens_errf(err, path, 0, "out of memory");
            return -1;
        }
    }
    int32_t lines = 1;
    exr_get_scanlines_per_chunk(f, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (long y = dw.min.y; y <= dw.max.y && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_read_scanline_chunk_info(f, 0, (int)y, &ci);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_decoding_update(f, 0, &ci, &dec) : exr_decoding_initialize(f, 0, &ci, &dec);
        if (rv != EXR_ERR_SUCCESS)
            break;
        long row = ci.start_y - dw.min.y;
        for (int k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            int c = find_name(img->nchannels, (const char *const *)img->names, ch->channel_name);
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)(sizeof(float) * (size_t)w);
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->decode_to_ptr = (uint8_t *)(img->planes[c] + (size_t)row * (size_t)w);
        }
        if (!started) {
            rv = exr_decoding_choose_default_routines(f, 0, &dec);
            started = 1;
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(f, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(f, &dec);
    if (rv != EXR_ERR_SUCCESS)
        return fail(err, path, "cannot read EXR data", rv);
    return 0;
}

int exr_read_float(const char *path, exr_image *img, lens_err *err)
{
    memset(img, 0, sizeof *img);
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    exr_context_t f = NULL;
    exr_result_t rv = exr_start_read(&f, path, &init);
    if (rv != EXR_ERR_SUCCESS)
        return fail(err, path, "cannot open as EXR", rv);
    int bad = read_body(f, img, path, err);
    exr_finish(&f);
    if (bad)
        exr_image_free(img);
    return bad ? -1 : 0;
}
