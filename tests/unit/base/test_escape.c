/* The escapers (escape.h) on hostile strings: what each output language may never see
 * (a comment's end, markup, a raw quote, ill-formed UTF-8) is absent, and what can be
 * kept comes back: the C comment's \xNN decode to the bytes, a valid UTF-8 name is
 * unchanged in XML and JSON, a Latin-1 byte becomes its character. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/escape.h"

static const char *const hostile[] = {
    "*/ (void)\"INJECTED\"; /*", "a*/", "/*", "end\\", "two\nlines", "q\"uote", "<b>&amp;",
    "]]>", "\x01\x02\x1b[31m\x7f", "f\xc3\x28\xff", "Objektiv f\xfcr", "?\?/", "a?\?=b", "*", "/",
    "\xed\xa0\x80 \xc0\xaf \xf4\x90\x80\x80", "", "\xe2\x80\xa8"};
#define NHOSTILE (sizeof hostile / sizeof *hostile)

/* What fn writes for s, as a string the caller frees. */
static char *written(void (*fn)(FILE *, const char *), const char *s)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    fn(f, s);
    fclose(f);
    return buf;
}

/* Well-formed UTF-8 (RFC 3629), checked by its own table of lead bytes. */
static int valid_utf8(const char *str)
{
    const unsigned char *s = (const unsigned char *)str;
    while (*s) {
        int n;
        unsigned long v;
        if (s[0] < 0x80) { s++; continue; }
        else if (s[0] >= 0xC2 && s[0] <= 0xDF) n = 1, v = s[0] & 0x1F;
        else if (s[0] >= 0xE0 && s[0] <= 0xEF) n = 2, v = s[0] & 0x0F;
        else if (s[0] >= 0xF0 && s[0] <= 0xF4) n = 3, v = s[0] & 0x07;
        else return 0;
        for (int k = 1; k <= n; k++) {
            if ((s[k] & 0xC0) != 0x80) return 0;
            v = v << 6 | (s[k] & 0x3F);
        }
        if ((n == 2 && v < 0x800) || (n == 3 && v < 0x10000) || (v >= 0xD800 && v <= 0xDFFF) ||
            v > 0x10FFFF)
            return 0;
        s += n + 1;
    }
    return 1;
}

static void test_c_comment(void **st)
{
    (void)st;
    for (size_t k = 0; k < NHOSTILE; k++) {
        char *c = written(text_c_comment, hostile[k]);
        /* the text sits between spaces inside a comment: neither it nor its edges may
         * close or open a comment, splice a line or make a trigraph */
        for (const char *p = c; *p; p++) {
            assert_true(*p >= 0x20 && *p < 0x7F);
            assert_false(*p == '*');
            assert_false(p[0] == '?' && p[1] == '?');
            if (*p == '\\')
                assert_true(p[1] == 'x');
        }
        /* and the bytes come back */
        char back[256];
        size_t n = 0;
        for (const char *p = c; *p; n++)
            if (p[0] == '\\') {
                unsigned v;
                assert_int_equal(sscanf(p + 2, "%2x", &v), 1);
                back[n] = (char)v, p += 4;
            } else {
                back[n] = *p++;
            }
        back[n] = 0;
        assert_string_equal(back, hostile[k]);
        free(c);
    }
}

static void test_xml(void **st)
{
    (void)st;
    for (size_t k = 0; k < NHOSTILE; k++) {
        char *x = written(text_xml, hostile[k]);
        assert_true(valid_utf8(x));
        assert_null(strpbrk(x, "<>\"'\x01\x02\x1b\x7f"));
        for (size_t i = 0; x[i]; i++) /* every & begins an entity */
            if (x[i] == '&')
                assert_true(!strncmp(x + i, "&amp;", 5) || !strncmp(x + i, "&lt;", 4) ||
                            !strncmp(x + i, "&gt;", 4) || !strncmp(x + i, "&quot;", 6) ||
                            !strncmp(x + i, "&apos;", 6));
        free(x);
    }
    char *x = written(text_xml, "Taylor & Hobson <Cooke> ]]>");
    assert_string_equal(x, "Taylor &amp; Hobson &lt;Cooke&gt; ]]&gt;");
    free(x);
    x = written(text_xml, "Objektiv f\xfcr 10\xc2\xb5m"); /* Latin-1, then UTF-8 */
    assert_string_equal(x, "Objektiv f\xc3\xbcr 10\xc2\xb5m");
    free(x);
    x = written(text_xml, "a\x01z"); /* XML 1.0 has no U+0001, even as a reference */
    assert_string_equal(x, "a\xef\xbf\xbdz");
    free(x);
}

static void test_json(void **st)
{
    (void)st;
    for (size_t k = 0; k < NHOSTILE; k++) {
        char *j = written(text_json, hostile[k]);
        assert_true(valid_utf8(j));
        size_t n = strlen(j);
        assert_true(n >= 2 && j[0] == '"' && j[n - 1] == '"');
        for (size_t i = 1; i + 1 < n; i++) { /* no raw quote or control inside */
            assert_true((unsigned char)j[i] >= 0x20 && j[i] != 0x7F);
            if (j[i] == '\\')
                i++; /* the escaped character */
            else
                assert_true(j[i] != '"');
        }
        free(j);
    }
    char *j = written(text_json, "a\"b\\c\nd\x01");
    assert_string_equal(j, "\"a\\\"b\\\\c\\nd\\u0001\"");
    free(j);
    j = written(text_json, "f\xc3\xbcr \xe2\x82\xac \xf0\x9f\x94\x8d"); /* valid: as it is */
    assert_string_equal(j, "\"f\xc3\xbcr \xe2\x82\xac \xf0\x9f\x94\x8d\"");
    free(j);
    j = written(text_json, "f\xfcr \xc0\xaf"); /* Latin-1 bytes, an overlong '/' */
    assert_string_equal(j, "\"f\xc3\xbcr \xc3\x80\xc2\xaf\"");
    free(j);
}

static void test_utf8_for_pictures(void **st)
{
    (void)st;
    char buf[64];
    for (size_t k = 0; k < NHOSTILE; k++) {
        size_t need = text_utf8(buf, sizeof buf, hostile[k]);
        assert_true(valid_utf8(buf));
        assert_int_equal(strlen(buf), need); /* all fit here */
        for (const char *p = buf; *p; p++)
            assert_true((unsigned char)*p >= 0x20 && *p != 0x7F);
    }
    assert_int_equal(text_utf8(buf, sizeof buf, "Objektiv f\xfcr"), 13);
    assert_string_equal(buf, "Objektiv f\xc3\xbcr");
    /* cut between characters, never inside one; the length needed is still told */
    assert_int_equal(text_utf8(buf, 3, "\xc3\xbc\xc3\xbc"), 4);
    assert_string_equal(buf, "\xc3\xbc");
    assert_int_equal(text_utf8(buf, 2, "\xfc"), 2);
    assert_string_equal(buf, "");
}

static void test_prefix(void **st)
{
    (void)st;
    const char *why;
    assert_true(text_c_prefix_ok("lens_poly", &why));
    assert_null(why);
    assert_true(text_c_prefix_ok("cam2", &why));
    const char *bad[] = {"", "9x", "a-b", "a b", "f\xfc", "sqrt", "NAN", "INFINITY", "M_PI",
                         "_x", "__y", "int", "restrict", "class", "new", "size_t", "main", "n",
                         "in", "pass"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_false(text_c_prefix_ok(bad[k], &why));
        assert_non_null(why);
    }
    char longname[80];
    memset(longname, 'a', 64);
    longname[64] = 0;
    assert_false(text_c_prefix_ok(longname, &why));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_c_comment), cmocka_unit_test(test_xml), cmocka_unit_test(test_json),
        cmocka_unit_test(test_utf8_for_pictures), cmocka_unit_test(test_prefix)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
