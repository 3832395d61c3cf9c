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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip),
        cmocka_unit_test(errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
