/* Option tables (options.h): every spelling of an option gives the same values, operands
 * are kept in order, "--" ends the options; and every command's documented defaults
 * (.def) are the values its *_default() function sets, so --help and the man page tell
 * the truth about them. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "sparselens/design_cli.h"
#include "sparselens/distort_cli.h"
#include "sparselens/eval_cli.h"
#include "sparselens/fit_cli.h"
#include "sparselens/info_cli.h"
#include "sparselens/options.h"
#include "sparselens/render_cli.h"
#include "sparselens/spot_cli.h"
#include "sparselens/trace_cli.h"
#include "sparselens/numparse.h"

typedef struct {
    int all, quiet;
    long count;
    int small;
    double x;
    int mode;
    const char *name;
} toy;

static const opt_choice modes[] = {{"one", 1}, {"two", 2}, {NULL, 0}};
static const opt_spec toy_table[] = {
    {'a', "all", NULL, OPT_FLAG, OPT_AT(toy, all), .help = "a flag"},
    {'q', "quiet", NULL, OPT_FLAG, OPT_AT(toy, quiet), .help = "another"},
    {'n', NULL, "N", OPT_INT, OPT_AT(toy, count), .lo = 0, .hi = 1e12, .help = "a count"},
    {0, "small", "N", OPT_INT, OPT_AT(toy, small), .lo = -5, .hi = 5, .help = "an int"},
    {'x', "x-value", "X", OPT_DOUBLE, OPT_AT(toy, x), .help = "a number"},
    {0, "mode", NULL, OPT_CHOICE, OPT_AT(toy, mode), .choices = modes, .help = "a word"},
    {'o', "output", "FILE", OPT_STRING, OPT_AT(toy, name), .help = "a string"},
    {0}};
static const opt_command toy_command = {"lens-toy", "[options] FILE", "A toy.", toy_table};

/* Parses a space-separated command line (no quoting) into a toy. */
static int parse(const char *line, toy *t, const char **ops, int max)
{
    static char buf[512];
    static char *argv[64];
    snprintf(buf, sizeof buf, "lens-toy %s", line);
    int argc = 0;
    for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
        argv[argc++] = tok;
    memset(t, 0, sizeof *t);
    return opt_parse(&toy_command, argc, argv, t, ops, max);
}

static void spellings_agree(void **state)
{
    (void)state;
    const char *lines[] = {
        "-a -q -n 7 --small -3 -x 2.5 --mode two -o out.txt in.txt",
        "-aq -n7 --small=-3 --x-value=2.5 --mode=two -oout.txt in.txt",
        "in.txt -qan7 --small -3 --x-value 2.5 --mode two --output out.txt",
        "--all --quiet -n 7e0 --small=-3 -x2.5 --mode=two --output=out.txt -- in.txt",
    };
    for (size_t k = 0; k < sizeof lines / sizeof *lines; k++) {
        toy t;
        const char *ops[2] = {NULL, NULL};
        assert_int_equal(parse(lines[k], &t, ops, 2), 1);
        assert_int_equal(t.all, 1);
        assert_int_equal(t.quiet, 1);
        assert_int_equal(t.count, 7);
        assert_int_equal(t.small, -3);
        assert_true(t.x == 2.5);
        assert_int_equal(t.mode, 2);
        assert_string_equal(t.name, "out.txt");
        assert_string_equal(ops[0], "in.txt");
    }
}

static void operands_and_double_dash(void **state)
{
    (void)state;
    toy t;
    const char *ops[4];
    /* "-" is an operand (standard input); after "--" even "-a" is one */
    assert_int_equal(parse("- b -n 3 -- -a --all", &t, ops, 4), 4);
    assert_string_equal(ops[0], "-");
    assert_string_equal(ops[1], "b");
    assert_string_equal(ops[2], "-a");
    assert_string_equal(ops[3], "--all");
    assert_int_equal(t.all, 0);
    assert_int_equal(t.count, 3);
    /* a value that starts with '-' is taken as the value when one is due */
    assert_int_equal(parse("-o -weird", &t, ops, 4), 0);
    assert_string_equal(t.name, "-weird");
    /* counts beyond 32 bits land whole in an 8-byte field */
    assert_int_equal(parse("-n 1e11", &t, ops, 4), 0);
    assert_true(t.count == 100000000000L);
}

/* Walks a table (and its groups) and checks each .def that names a value against the
 * defaults struct. */
static int check_defaults(const opt_spec *table, const char *base, size_t offset,
                          const char *cmd)
{
    int checked = 0;
    for (const opt_spec *s = table; s->type != OPT_END; s++) {
        const char *field = base + offset + s->offset;
        if (s->type == OPT_GROUP) {
            checked += check_defaults(s->group, base, offset + s->offset, cmd);
            continue;
        }
        if (!s->def)
            continue;
        double d;
        long l;
        if (s->type == OPT_INT && parse_long(s->def, &l) == 0) {
            long have = 0;
            if (s->size == 4) {
                int32_t v;
                memcpy(&v, field, 4);
                have = v;
            } else {
                int64_t v;
                memcpy(&v, field, 8);
                have = (long)v;
            }
            if (have != l)
                fail_msg("%s --%s: documented default %s, set %ld", cmd, s->long_name, s->def,
                         have);
            checked++;
        } else if ((s->type == OPT_DOUBLE || s->type == OPT_POSITIVE) &&
                   parse_double(s->def, &d) == 0) {
            double have;
            memcpy(&have, field, sizeof have);
            if (have != d)
                fail_msg("%s --%s: documented default %s, set %g", cmd, s->long_name, s->def,
                         have);
            checked++;
        } else if (s->type == OPT_CHOICE && strchr(s->def, ' ') == NULL) {
            /* a one-word default must be one of the words (a phrase describes an unset one) */
            int have;
            memcpy(&have, field, sizeof have);
            const opt_choice *c = s->choices;
            while (c->name && strcmp(c->name, s->def) != 0)
                c++;
            if (!c->name || c->value != have)
                fail_msg("%s --%s: documented default %s, set %d", cmd, s->long_name, s->def,
                         have);
            checked++;
        } else if (s->type == OPT_STRING && strchr(s->def, ' ') == NULL &&
                   strcmp(s->def, "all") != 0) {
            /* a one-word string default is the value itself */
            const char *have;
            memcpy(&have, field, sizeof have);
            if (!have || strcmp(have, s->def) != 0)
                fail_msg("%s --%s: documented default %s, set %s", cmd, s->long_name, s->def,
                         have ? have : "NULL");
            checked++;
        }
    }
    return checked;
}

static void documented_defaults_are_the_defaults(void **state)
{
    (void)state;
    int n = 0;
    {
        fit_cli o;
        fit_cli_default(&o);
        n += check_defaults(fit_command.table, (const char *)&o, 0, "lens-fit");
    }
    {
        trace_cli o;
        trace_cli_default(&o);
        n += check_defaults(trace_command.table, (const char *)&o, 0, "lens-trace");
        lens_cli_options_free(&o.lens);
    }
    {
        info_cli o;
        info_cli_default(&o);
        n += check_defaults(info_command.table, (const char *)&o, 0, "lens-info");
        lens_cli_options_free(&o.lens);
    }
    {
        eval_cli o;
        eval_cli_default(&o);
        n += check_defaults(eval_command.table, (const char *)&o, 0, "lens-eval");
    }
    {
        spot_cli o;
        spot_cli_default(&o);
        n += check_defaults(spot_command.table, (const char *)&o, 0, "lens-spot");
        lens_cli_options_free(&o.im.lopt);
    }
    {
        distort_cli o;
        distort_cli_default(&o);
        n += check_defaults(distort_command.table, (const char *)&o, 0, "lens-distort");
        lens_cli_options_free(&o.im.lopt);
    }
    {
        render_cli o;
        render_cli_default(&o);
        n += check_defaults(render_command.table, (const char *)&o, 0, "lens-render");
        lens_cli_options_free(&o.lens);
    }
    {
#define DESIGN_DEFAULTS(type, fn, cmd, name)                                  \
    {                                                                         \
        type o;                                                               \
        fn(&o);                                                               \
        n += check_defaults(cmd.table, (const char *)&o, 0, name);            \
        lens_cli_options_free(&o.im.lopt);                                    \
    }
        DESIGN_DEFAULTS(fan_cli, fan_cli_default, fan_command, "lens-fan")
        DESIGN_DEFAULTS(field_cli, field_cli_default, field_command, "lens-field")
        DESIGN_DEFAULTS(mtf_cli, mtf_cli_default, mtf_command, "lens-mtf")
        DESIGN_DEFAULTS(layout_cli, layout_cli_default, layout_command, "lens-layout")
#undef DESIGN_DEFAULTS
    }
    assert_true(n >= 30); /* the walk reached the tables' numbers, words and names */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spellings_agree),
        cmocka_unit_test(operands_and_double_dash),
        cmocka_unit_test(documented_defaults_are_the_defaults),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
