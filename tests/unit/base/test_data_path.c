/* Finding files by name (data_path.h): the order ./, $ENV directories, shipped
 * directories; extensions; paths anchored to a directory taken as they are; and the
 * shipped lenses found beside this test binary (build/tests/../../lenses). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sparselens/data_path.h"

static const char *const exts[] = {".lens", ".zmx", NULL};
static char dir[64], cwd[4096];

static void touch(const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("x\n", f);
    fclose(f);
}

static int setup(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/test_data_path_XXXXXX");
    if (!mkdtemp(dir) || !getcwd(cwd, sizeof cwd))
        return -1;
    char p[256];
    snprintf(p, sizeof p, "%s/a", dir);
    if (mkdir(p, 0700) != 0) return -1;
    snprintf(p, sizeof p, "%s/b", dir);
    if (mkdir(p, 0700) != 0) return -1;
    unsetenv("TEST_DATA_PATH");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    if (chdir(cwd) != 0) return -1;
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void test_env_order_and_extensions(void **state)
{
    (void)state;
    char p[256], buf[256], want[256];
    snprintf(p, sizeof p, "%s/a/mine.zmx", dir);
    touch(p);
    snprintf(p, sizeof p, "%s/b/mine.lens", dir);
    touch(p);
    snprintf(p, sizeof p, "%s/nowhere:%s/b:%s/a", dir, dir, dir);
    setenv("TEST_DATA_PATH", p, 1);
    /* b comes first in the list, so b's file wins although a's is also a match */
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "mine", exts, buf, sizeof buf), 0);
    snprintf(want, sizeof want, "%s/b/mine.lens", dir);
    assert_string_equal(buf, want);
    /* the exact name before any extension */
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "mine.zmx", exts, buf, sizeof buf), 0);
    snprintf(want, sizeof want, "%s/a/mine.zmx", dir);
    assert_string_equal(buf, want);
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "nosuch", exts, buf, sizeof buf), -1);
}

static void test_cwd_first_and_anchored_paths(void **state)
{
    (void)state;
    char p[256], buf[256];
    snprintf(p, sizeof p, "%s/b/here.lens", dir);
    touch(p);
    snprintf(p, sizeof p, "%s/b", dir);
    setenv("TEST_DATA_PATH", p, 1);
    assert_int_equal(chdir(dir), 0);
    touch("here.lens");
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "here", exts, buf, sizeof buf), 0);
    assert_string_equal(buf, "here.lens");
    /* anchored paths are never looked up, even when missing */
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "./gone.lens", exts, buf, sizeof buf), 0);
    assert_string_equal(buf, "./gone.lens");
    assert_int_equal(data_find("lenses", "TEST_DATA_PATH", "/gone/x.lens", exts, buf, sizeof buf), 0);
    assert_string_equal(buf, "/gone/x.lens");
    assert_int_equal(chdir(cwd), 0);
}

/* This binary is build/tests/test_data_path: the source tree's lenses are ../../lenses. */
static void test_shipped_beside_the_binary(void **state)
{
    (void)state;
    char buf[4096], want[4200];
    assert_int_equal(chdir(dir), 0); /* not the source tree */
    assert_int_equal(data_find("lenses", NULL, "dgauss.50mm", exts, buf, sizeof buf), 0);
    snprintf(want, sizeof want, "%s/lenses/dgauss.50mm.lens", cwd);
    assert_string_equal(buf, want);
    assert_int_equal(data_find("lenses", NULL, "reference/pbrt/wide.dat", exts, buf, sizeof buf), 0);
    snprintf(want, sizeof want, "%s/lenses/reference/pbrt/wide.dat", cwd);
    assert_string_equal(buf, want);
    assert_int_equal(data_shipped_file("scenes", "dgauss.scene", buf, sizeof buf), 0);
    snprintf(want, sizeof want, "%s/scenes/dgauss.scene", cwd);
    assert_string_equal(buf, want);
    assert_int_equal(chdir(cwd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_env_order_and_extensions),
        cmocka_unit_test(test_cwd_first_and_anchored_paths),
        cmocka_unit_test(test_shipped_beside_the_binary),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
