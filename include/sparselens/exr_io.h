#ifndef SPARSELENS_EXR_IO_H
#define SPARSELENS_EXR_IO_H
/* Float images with named channels in OpenEXR files, through the OpenEXR Core C API
 * (src/base/exr_io.c is the only file that includes it). Single-part scanline files, 32-bit
 * float channels, ZIP compression (a chunk that does not shrink is stored raw), data window (0,0)-(width-1,height-1).
 * Pixel (x, y) of a channel plane is at plane[y * width + x], y = 0 at the top. */
#include "sparselens/diag.h"

/* Writes nchannels planes (names[c], planes[c]) through a temporary file and
 * outfile_commit_path, so no partial file is left. The temporary file is read back and
 * compared bit for bit before it is renamed into place: a file that would not read back
 * as written is an error, never a result. Names must be distinct and non-empty.
 * 0 on success. */
int exr_write_float(const char *path, int width, int height, int nchannels,
                    const char *const *names, const float *const *planes, lens_err *err);

typedef struct {
    int width, height, nchannels;
    char **names;  /* as stored in the file: OpenEXR keeps channels sorted by name */
    float **planes; /* converted to float whatever the stored type (half, uint) */
} exr_image;

/* Reads every channel of the first part. 0 on success; img is empty on failure. */
int exr_read_float(const char *path, exr_image *img, lens_err *err);
/* The plane of the named channel, or NULL. */
const float *exr_image_channel(const exr_image *img, const char *name);
void exr_image_free(exr_image *img);

#endif
