/* lens-trace's job without a process: every generated row is what the exact tracer gives
 * for its inputs, one ray at a time (trace_sample), the stop hit lies within the stop;
 * and a stream keeps its rows aligned, a bad row coming out as nan and reported with its
 * line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_lenses.h"
#include "sparselens/trace_run.h"

static lens_t lens;

static int setup(void **state)
{
    (void)state;
    if (fixture_dgauss50(&lens) != 0)
        return -1;
    lens.sensor_w = 36, lens.sensor_h = 24;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    lens_free(&lens);
    return 0;
}

/* Runs trace_run into a temporary file and opens it as samples. */
static samples_reader *run(trace_cli *o, samples_reader *in, long *bad, const trace_run_hooks *h,
                           char *path)
{
    strcpy(path, "/tmp/test_trace_run.XXXXXX");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    lens_err err;
    if (trace_run(o, &lens, in, f, h, bad, &err) != 0)
        fail_msg("%s", err.msg);
    fclose(f);
    samples_reader *r = samples_open(path, &err);
    assert_non_null(r);
    return r;
}

static void generated_rows_are_exact_traces(void **state)
{
    (void)state;
    trace_cli o;
    trace_cli_default(&o);
    o.lens_path = "dgauss";
    o.count = 300;
    o.seed = 7;
    o.passing_only = 1;
    o.stop_columns = 1, o.clip_columns = 0; /* ap_x ap_y, no pilot */
    char path[64];
    long bad;
    samples_reader *r = run(&o, NULL, &bad, NULL, path);
    static const char *const cols[] = {"x", "y", "u", "v", "lambda", "out_x", "out_y",
                                       "out_u", "out_v", "out_eta", "ap_x", "ap_y"};
    int map[12];
    lens_err err;
    assert_int_equal(samples_map(r, cols, 12, map, &err), 0);
    double vals[64], *n = malloc(lens.nsurf * sizeof *n);
    int rows = 0;
    while (samples_next(r, vals, &err) > 0) {
        double in[4] = {vals[map[0]], vals[map[1]], vals[map[2]], vals[map[3]]}, out[4];
        assert_int_equal(lens_indices(&lens, vals[map[4]], n, &err), 0);
        trace_result res = trace_sample(&lens, n, TRACE_TO_OUTER, in, out);
        assert_int_equal(res.status, TRACE_PASSED); /* --passing-only */
        for (int k = 0; k < 4; k++)
            if (!(fabs(out[k] - vals[map[5 + k]]) <= 1e-9))
                fail_msg("row %d out %d: %.17g vs %.17g", rows, k, vals[map[5 + k]], out[k]);
        assert_true(fabs(res.transmittance - vals[map[9]]) <= 1e-12);
        double sd = lens.surf[lens.stop].semi_diameter;
        assert_true(hypot(vals[map[10]], vals[map[11]]) <= sd * (1 + 1e-12));
        rows++;
    }
    assert_int_equal(rows, 300);
    assert_int_equal(bad, 0);
    free(n);
    samples_close(r);
    remove(path);
}

typedef struct {
    int calls;
    char msg[LENS_ERR_MAX];
} bad_log;

static void on_bad(void *ctx, const lens_err *err)
{
    bad_log *b = ctx;
    b->calls++;
    snprintf(b->msg, sizeof b->msg, "%s", err->msg);
}

static void stream_keeps_rows_aligned(void **state)
{
    (void)state;
    char in_path[] = "/tmp/test_trace_run_in.XXXXXX";
    int fd = mkstemp(in_path);
    FILE *f = fdopen(fd, "w");
    fprintf(f, "# columns: id x y u v lambda\n"
               "1 0 0 0.01 0 0.55\n"
               "2 1 2 nan 0 0.55\n"
               "3 3 -1 -0.02 0.01 0.6\n");
    fclose(f);
    lens_err err;
    samples_reader *in = samples_open(in_path, &err);
    assert_non_null(in);
    trace_cli o;
    trace_cli_default(&o);
    o.lens_path = "dgauss";
    o.from_stdin = 1;
    o.no_passage_columns = 1;
    bad_log log = {0};
    trace_run_hooks hooks = {on_bad, NULL, &log};
    long bad;
    char path[64];
    samples_reader *r = run(&o, in, &bad, &hooks, path);
    samples_close(in);
    assert_int_equal(bad, 1);
    assert_int_equal(log.calls, 1);
    assert_non_null(strstr(log.msg, ":3: x, y, u, v and lambda must be finite"));
    int cx = samples_find(r, "out_x"), cid = samples_find(r, "id");
    assert_true(cx >= 0 && cid > cx); /* the id passes through, after the traced columns */
    double vals[64];
    double got[3];
    int rows = 0;
    while (rows < 3 && samples_next(r, vals, &err) > 0) {
        assert_true(vals[cid] == rows + 1);
        got[rows++] = vals[cx];
    }
    assert_int_equal(rows, 3);
    assert_true(isfinite(got[0]) && isnan(got[1]) && isfinite(got[2]));
    samples_close(r);
    remove(path);
    remove(in_path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(generated_rows_are_exact_traces),
        cmocka_unit_test(stream_keeps_rows_aligned),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
