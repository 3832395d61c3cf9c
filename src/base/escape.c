/* The escapers of escape.h: one reading of bytes as characters (well-formed UTF-8, else
 * Latin-1 byte by byte), then one writer per output language. */
#include "sparselens/escape.h"

#include <ctype.h>
#include <string.h>

/* The character at *p, *p moved past it. A sequence is taken only when well formed:
 * the shortest form, no surrogate, at most U+10FFFF. */
static unsigned long next_char(const unsigned char **p)
{
    const unsigned char *s = *p;
    unsigned long c = s[0];
    int n = c >= 0xF0 && c <= 0xF4 ? 3 : c >= 0xE0 ? (c < 0xF0 ? 2 : 0) : c >= 0xC2 ? 1 : 0;
    if (c < 0x80 || n == 0) {
        *p = s + 1;
        return c;
    }
    unsigned long v = c & (0x3F >> n);
    for (int k = 1; k <= n; k++) {
        if ((s[k] & 0xC0) != 0x80) { /* the NUL ends it too */
            *p = s + 1;
            return c;
        }
        v = v << 6 | (s[k] & 0x3F);
    }
    static const unsigned long least[4] = {0, 0x80, 0x800, 0x10000};
    if (v < least[n] || (v >= 0xD800 && v <= 0xDFFF) || v > 0x10FFFF) {
        *p = s + 1;
        return c;
    }
    *p = s + 1 + n;
    return v;
}

/* c as UTF-8 into u (4 bytes); returns its length. */
static int put_utf8(unsigned long c, char u[4])
{
    if (c < 0x80)
        return u[0] = (char)c, 1;
    if (c < 0x800)
        return u[0] = (char)(0xC0 | c >> 6), u[1] = (char)(0x80 | (c & 0x3F)), 2;
    if (c < 0x10000)
        return u[0] = (char)(0xE0 | c >> 12), u[1] = (char)(0x80 | (c >> 6 & 0x3F)),
               u[2] = (char)(0x80 | (c & 0x3F)), 3;
    return u[0] = (char)(0xF0 | c >> 18), u[1] = (char)(0x80 | (c >> 12 & 0x3F)),
           u[2] = (char)(0x80 | (c >> 6 & 0x3F)), u[3] = (char)(0x80 | (c & 0x3F)), 4;
}

static int is_control(unsigned long c)
{
    return c < 0x20 || (c >= 0x7F && c < 0xA0);
}

#define REPLACEMENT 0xFFFDul

size_t text_utf8(char *dst, size_t cap, const char *s)
{
    size_t len = 0, kept = 0; /* kept < len once a character did not fit: none after it */
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p;) {
        unsigned long c = next_char(&p);
        char u[4];
        size_t n = (size_t)put_utf8(is_control(c) ? REPLACEMENT : c, u);
        if (kept == len && kept + n < cap) {
            memcpy(dst + kept, u, n);
            kept += n;
        }
        len += n;
    }
    if (cap)
        dst[kept] = 0;
    return len;
}

void text_c_comment(FILE *f, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        int plain = *p >= 0x20 && *p < 0x7F && *p != '*' && *p != '\\' &&
                    !(*p == '?' && p[1] == '?');
        if (plain)
            fputc(*p, f);
        else
            fprintf(f, "\\x%02x", *p);
    }
}

void text_xml(FILE *f, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p;) {
        unsigned long c = next_char(&p);
        const char *entity = c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;"
                           : c == '"' ? "&quot;" : c == '\'' ? "&apos;" : NULL;
        if (entity) {
            fputs(entity, f);
            continue;
        }
        if ((c < 0x20 && c != '\t' && c != '\n') || c == 0x7F || (c >= 0x80 && c < 0xA0) ||
            c == 0xFFFE || c == 0xFFFF)
            c = REPLACEMENT;
        char u[4];
        fwrite(u, 1, (size_t)put_utf8(c, u), f);
    }
}

void text_json(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p;) {
        unsigned long c = next_char(&p);
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", (int)c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c == '\t')
            fputs("\\t", f);
        else if (c < 0x20 || c == 0x7F || (c >= 0x80 && c < 0xA0) || c == 0x2028 || c == 0x2029)
            fprintf(f, "\\u%04lx", c);
        else {
            char u[4];
            fwrite(u, 1, (size_t)put_utf8(c, u), f);
        }
    }
    fputc('"', f);
}

static int in_list(const char *name, const char *const *list, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (strcmp(name, list[k]) == 0)
            return 1;
    return 0;
}

int text_c_prefix_ok(const char *name, const char **why)
{
    /* C11's and C++17's keywords (a generated file compiles as either) */
    static const char *const keywords[] = {
        "auto", "break", "case", "char", "const", "continue", "default", "do", "double",
        "else", "enum", "extern", "float", "for", "goto", "if", "inline", "int", "long",
        "register", "restrict", "return", "short", "signed", "sizeof", "static", "struct",
        "switch", "typedef", "union", "unsigned", "void", "volatile", "while", "alignas",
        "alignof", "and", "and_eq", "asm", "bitand", "bitor", "bool", "catch", "char16_t",
        "char32_t", "class", "compl", "const_cast", "constexpr", "decltype", "delete",
        "dynamic_cast", "explicit", "export", "false", "friend", "mutable", "namespace",
        "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq", "private",
        "protected", "public", "reinterpret_cast", "static_assert", "static_cast",
        "template", "this", "thread_local", "throw", "true", "try", "typeid", "typename",
        "using", "virtual", "wchar_t", "xor", "xor_eq", "main"};
    /* what the generated file's headers declare (C11 7.12, 7.19; POSIX's M_ constants) */
    static const char *const declared[] = {
        "acos", "acosh", "asin", "asinh", "atan", "atan2", "atanh", "cbrt", "ceil",
        "copysign", "cos", "cosh", "erf", "erfc", "exp", "exp2", "expm1", "fabs", "fdim",
        "floor", "fma", "fmax", "fmin", "fmod", "frexp", "hypot", "ilogb", "ldexp", "lgamma",
        "llrint", "llround", "log", "log10", "log1p", "log2", "logb", "lrint", "lround",
        "modf", "nan", "nearbyint", "nextafter", "nexttoward", "pow", "remainder", "remquo",
        "rint", "round", "scalbln", "scalbn", "sin", "sinh", "sqrt", "tan", "tanh", "tgamma",
        "trunc", "j0", "j1", "jn", "y0", "y1", "yn", "gamma", "drem", "finite", "significand",
        "signgam", "float_t", "double_t", "NAN", "INFINITY", "HUGE_VAL", "HUGE_VALF",
        "HUGE_VALL", "FP_INFINITE", "FP_NAN", "FP_NORMAL", "FP_SUBNORMAL", "FP_ZERO",
        "FP_FAST_FMA", "FP_ILOGB0", "FP_ILOGBNAN", "MATH_ERRNO", "MATH_ERREXCEPT",
        "math_errhandling", "fpclassify", "isfinite", "isinf", "isnan", "isnormal",
        "signbit", "isgreater", "isgreaterequal", "isless", "islessequal", "islessgreater",
        "isunordered", "size_t", "ptrdiff_t", "wchar_t", "max_align_t", "NULL", "offsetof",
        "errno", "assert", "std"};
    /* the generated one-ray function is called by name beside the batch function's
     * parameters and locals (poly_emit_c.c) */
    static const char *const locals[] = {"n", "in", "out", "pass", "b", "p"};
    const char *s = name;
    *why = NULL;
    if (!s || !(isalpha((unsigned char)*s) || *s == '_')) {
        *why = "not a C identifier (a letter first, then letters, digits and '_')";
        return 0;
    }
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || isdigit((unsigned char)*s) ||
              *s == '_')) {
            *why = "not a C identifier (a letter first, then letters, digits and '_')";
            return 0;
        }
    if (name[0] == '_')
        *why = "reserved (C reserves names that begin with '_' for the implementation)";
    else if (strlen(name) > 63)
        *why = "longer than 63 characters (C11 5.2.4.1)";
    else if (in_list(name, keywords, sizeof keywords / sizeof *keywords))
        *why = "a C or C++ keyword";
    else if (in_list(name, declared, sizeof declared / sizeof *declared) ||
             strncmp(name, "M_", 2) == 0 || strncmp(name, "FP_", 3) == 0 ||
             strncmp(name, "__", 2) == 0)
        *why = "declared by <math.h> or <stddef.h>, which the generated file includes";
    else if (in_list(name, locals, sizeof locals / sizeof *locals))
        *why = "a name the generated code uses for a variable";
    return *why == NULL;
}

void text_line(FILE *f, const char *s)
{
    text_line_n(f, s, strlen(s));
}

int text_control_escape(unsigned char c, char out[4])
{
    static const char hex[] = "0123456789abcdef";
    if (c >= 0x20 && c != 0x7f)
        return 0;
    out[0] = '\\', out[1] = 'x', out[2] = hex[c >> 4], out[3] = hex[c & 15];
    return 4;
}

void text_line_n(FILE *f, const char *s, size_t n)
{
    for (const unsigned char *p = (const unsigned char *)s, *e = p + n; p < e; p++) {
        char esc[4];
        if (text_control_escape(*p, esc))
            fwrite(esc, 1, 4, f);
        else
            fputc(*p, f);
    }
}
