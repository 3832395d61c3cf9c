/* libFuzzer target: the C emitter on any system the .poly reader accepts (poly_emit_c,
 * poly_emit_c_header). Names from the file may reach only comments, so outside them the
 * generated text is the emitter's own: ASCII without a backslash (no line is spliced),
 * and no string literal but the emitter's few; no comment holds a "/" "*" (it would
 * mean a name had been able to close one and start another).
 * needs: src/poly/poly_emit_c.c src/base/escape.c */
#include "fuzz_common.h"
#include "sparselens/poly.h"

static const char *const own_strings[] = {"\"C\"", "\"arch=x86-64-v4\"", "\"arch=x86-64-v3\"",
                                          "\"default\"", "\"tune=generic\""};

/* The invariants above on one generated file. */
static void check_generated(const char *text, size_t len)
{
    FUZZ_CHECK(strlen(text) == len); /* no NUL inside */
    for (const char *p = text; *p;) {
        if (p[0] == '/' && p[1] == '*') {
            const char *end = strstr(p + 2, "*/");
            FUZZ_CHECK(end != NULL);
            for (const char *q = p + 2; q < end; q++)
                FUZZ_CHECK(!(q[0] == '/' && q[1] == '*'));
            p = end + 2;
            continue;
        }
        FUZZ_CHECK(!(p[0] == '/' && p[1] == '/'));
        FUZZ_CHECK(*p != '\\' && *p != '\'');
        FUZZ_CHECK((*p >= 0x20 && *p < 0x7F) || *p == '\n');
        if (*p == '"') {
            size_t k = 0, n = sizeof own_strings / sizeof *own_strings;
            while (k < n && strncmp(p, own_strings[k], strlen(own_strings[k])) != 0)
                k++;
            FUZZ_CHECK(k < n);
            p += strlen(own_strings[k]);
            continue;
        }
        p++;
    }
}

static void emit_and_check(int (*emit)(FILE *, const poly_system *, const char *),
                           const poly_system *sys)
{
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    FUZZ_CHECK(m != NULL);
    FUZZ_CHECK(emit(m, sys, "fuzz_fn") == 0);
    fclose(m);
    check_generated(text, len);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_stream s;
    if (fuzz_stream_open(&s, data, size))
        return 0;
    poly_system *sys = NULL;
    lens_err err;
    int rc = poly_read_stream(s.f, "fuzz.poly", &sys, &err);
    fuzz_stream_close(&s);
    if (rc != 0)
        return 0;
    emit_and_check(poly_emit_c, sys);
    emit_and_check(poly_emit_c_header, sys);
    poly_free(sys);
    return 0;
}
