/* Helpers shared by the libFuzzer targets (tests/fuzz/fuzz_*.c, built by tools/fuzz.sh).
 *
 * The parsers take a FILE* or a path; the fuzzer hands us bytes. Streams come from
 * fmemopen over a private copy (so a parser may never write through the fuzzer's const
 * buffer unnoticed), paths from an anonymous memfd named /proc/self/fd/N: no temporary
 * file is ever left in /tmp, even when a run is killed.
 *
 * FUZZ_CHECK(cond) aborts when an invariant that is not about memory safety fails (a
 * lens that reads but does not read back, a passed ray with NaN outputs): libFuzzer then
 * saves the input like any crash. */
#ifndef SPARSELENS_FUZZ_COMMON_H
#define SPARSELENS_FUZZ_COMMON_H
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* memfd_create, fmemopen, open_memstream */
#endif
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#define FUZZ_CHECK(cond)                                                                 \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            fprintf(stderr, "%s:%d: invariant failed: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                     \
        }                                                                                \
    } while (0)

typedef struct {
    FILE *f;
    char *copy;
} fuzz_stream;

/* A read stream over data[0..size). fmemopen refuses size 0 on some C libraries, so an
 * empty input reads /dev/null instead. */
static inline int fuzz_stream_open(fuzz_stream *s, const uint8_t *data, size_t size)
{
    s->copy = NULL;
    if (size == 0) {
        s->f = fopen("/dev/null", "r");
        return s->f ? 0 : -1;
    }
    s->copy = malloc(size);
    if (!s->copy)
        return -1;
    memcpy(s->copy, data, size);
    s->f = fmemopen(s->copy, size, "r");
    if (!s->f) {
        free(s->copy);
        return -1;
    }
    return 0;
}

static inline void fuzz_stream_close(fuzz_stream *s)
{
    if (s->f)
        fclose(s->f);
    free(s->copy);
}

/* NUL-terminated copy for parsers of text in memory. */
static inline char *fuzz_strdup(const uint8_t *data, size_t size)
{
    char *t = malloc(size + 1);
    if (t) {
        memcpy(t, data, size);
        t[size] = 0;
    }
    return t;
}

/* A path whose contents are data: an anonymous memfd, reached as /proc/self/fd/N. The
 * descriptor is created once per process and rewritten for every input. */
static inline const char *fuzz_path(const uint8_t *data, size_t size)
{
    static int fd = -1;
    static char path[64];
    if (fd < 0) {
        fd = memfd_create("sparselens-fuzz", 0);
        if (fd < 0)
            abort();
        snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    }
    if (ftruncate(fd, 0) != 0)
        abort();
    size_t off = 0;
    while (off < size) {
        ssize_t w = pwrite(fd, data + off, size - off, (off_t)off);
        if (w <= 0)
            abort();
        off += (size_t)w;
    }
    return path;
}

/* Glass names in fuzzed lenses resolve against the shipped catalog (the fuzzers run from
 * the repository root; tools/fuzz.sh sets the variable too). */
static inline void fuzz_use_shipped_catalog(void)
{
    setenv("SPARSELENS_GLASS_CATALOG", "lenses/glass.catalog", 0);
}

#endif
