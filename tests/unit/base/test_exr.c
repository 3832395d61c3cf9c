/* EXR float images: write, read back, channels by name, errors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/exr_io.h"

static void round_trip(void **state)
{
    (void)state;
    /* odd size, more rows than one ZIP chunk (16 lines), channels not in sorted order */
    const int W = 37, H = 53;
    const char *names[3] = {"density.R", "Y", "count"};
    float *p[3];
    for (int c = 0; c < 3; c++) {
        p[c] = malloc(sizeof(float) * W * H);
        for (int i = 0; i < W * H; i++)
            p[c][i] = (float)(c * 1000 + i) * 0.5f;
    }
    char dir[] = "/tmp/test_exr_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/a.exr", dir);
    lens_err err;
    assert_int_equal(exr_write_float(path, W, H, 3, names, (const float *const *)p, &err), 0);
    exr_image img;
    assert_int_equal(exr_read_float(path, &img, &err), 0);
    assert_int_equal(img.width, W);
    assert_int_equal(img.height, H);
    assert_int_equal(img.nchannels, 3);
    /* the file keeps them sorted by name */
    assert_string_equal(img.names[0], "Y");
    assert_string_equal(img.names[1], "count");
    assert_string_equal(img.names[2], "density.R");
    for (int c = 0; c < 3; c++) {
        const float *q = exr_image_channel(&img, names[c]);
        assert_non_null(q);
        assert_memory_equal(q, p[c], sizeof(float) * W * H);
    }
    assert_null(exr_image_channel(&img, "Z"));
    exr_image_free(&img);
    /* no temporary file is left beside it */
    char cmd[300];
    snprintf(cmd, sizeof cmd, "test $(ls %s | wc -l) -eq 1", dir);
    assert_int_equal(system(cmd), 0);
    unlink(path);
    rmdir(dir);
    for (int c = 0; c < 3; c++)
        free(p[c]);
}

static void errors(void **state)
{
    (void)state;
    lens_err err;
    exr_image img;
    assert_int_not_equal(exr_read_float("/nonexistent.exr", &img, &err), 0);
    assert_non_null(strstr(err.msg, "/nonexistent.exr"));
    float v = 1;
    const float *p[2] = {&v, &v};
    const char *dup[2] = {"R", "R"};
    assert_int_not_equal(exr_write_float("/tmp/never.exr", 1, 1, 2, dup, p, &err), 0);
    assert_int_not_equal(access("/tmp/never.exr", F_OK), 0);
    const char *one[1] = {"R"};
    assert_int_not_equal(exr_write_float("/nonexistent/dir/x.exr", 1, 1, 1, one, p, &err), 0);
    /* a file that is not EXR */
    assert_int_not_equal(exr_read_float("/etc/hostname", &img, &err), 0);
}

/* Writes one channel and asserts it reads back bit for bit. */
static void write_read_equal(const char *path, int W, int H, const float *plane)
{
    const char *names[1] = {"Y"};
    lens_err err;
    assert_int_equal(exr_write_float(path, W, H, 1, names, &plane, &err), 0);
    exr_image img;
    assert_int_equal(exr_read_float(path, &img, &err), 0);
    assert_memory_equal(img.planes[0], plane, sizeof(float) * (size_t)W * (size_t)H);
    exr_image_free(&img);
}

/* Finite floats of random bits: nothing for zlib to find. */
static float noise_float(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    unsigned u = (unsigned)(*s >> 32) & 0xbf7fffffu; /* exponent below 255: finite */
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* OpenEXR Core 3.1 wrote a 16-line ZIP chunk that compressed to exactly its own size
 * as compressed, and read it back as raw: rows of garbage (a 120x80 render did this).
 * A chunk of 64x16 floats, its first k bytes random and the rest zero, passes through
 * "compressed size == raw size" for some k in this range (k = 4029 and 4030 with this
 * generator); every k must read back as written. Whole-noise images too. */
static void incompressible_chunks(void **state)
{
    (void)state;
    char dir[] = "/tmp/test_exr_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/n.exr", dir);
    enum { W = 64, H = 16 };
    static float p[W * H];
    unsigned char *b = (unsigned char *)p;
    for (int k = 3980; k <= 4096; k++) {
        memset(p, 0, sizeof p);
        unsigned s = 12345;
        for (int i = 0; i < k; i++) {
            s = s * 1103515245u + 12345u;
            b[i] = (unsigned char)(s >> 16);
        }
        for (int i = 0; i < W * H; i++) /* no inf or NaN: exponent below 255 */
            if ((b[4 * i + 3] & 0x7f) == 0x7f)
                b[4 * i + 3] &= 0x3f;
        write_read_equal(path, W, H, p);
    }
    unsigned long long seed = 7;
    static float noise[120 * 80];
    for (int i = 0; i < 120 * 80; i++)
        noise[i] = noise_float(&seed);
    write_read_equal(path, 120, 80, noise);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip),
        cmocka_unit_test(errors),
        cmocka_unit_test(incompressible_chunks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
