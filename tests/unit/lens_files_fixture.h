/* What the lens-file tests share (test_lens_io.c, test_import_table.c): a scratch
 * directory for files written by the tests (setup and teardown of the test group), the
 * repository's glass catalog for every look-up whatever the binary's place, and the
 * reference prescriptions. */
#ifndef LENS_FILES_FIXTURE_H
#define LENS_FILES_FIXTURE_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sparselens/lens.h"

#define REF "lenses/reference"
#define CATALOG "lenses/glass.catalog"

static char tmpdir[64];

static inline int setup(void **state)
{
    (void)state;
    strcpy(tmpdir, "/tmp/test_lens_files_XXXXXX");
    if (!mkdtemp(tmpdir))
        return -1;
    /* The default catalog for every look-up in these tests, whatever the binary's place. */
    setenv("SPARSELENS_GLASS_CATALOG", CATALOG, 1);
    return 0;
}

static inline int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

static inline const char *write_file(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

static inline void near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.15g, want %.15g (tol %g)", got, want, tol);
}

/* The reference files are part of the repository: missing means a broken checkout or a
 * test run from the wrong directory, never a reason to skip. */
static inline void need_reference(void)
{
    if (access(REF "/fx/fisheye-ii.fx", R_OK) != 0)
        fail_msg("%s: not readable (run from the repository root)", REF "/fx/fisheye-ii.fx");
}

static inline void load_ok(const char *path, lens_t *l)
{
    lens_err err;
    if (lens_load(path, NULL, l, &err) != 0)
        fail_msg("%s", err.msg);
}

#endif
