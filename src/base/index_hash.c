/* Hash index (see index_hash.h). */
#include "base/index_hash.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* The 64-bit finaliser of MurmurHash3 (public domain): every input bit reaches every
 * output bit, so the low bits used as a slot number are well spread. */
static uint64_t mix(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    h ^= h >> 33;
    return h;
}

uint64_t index_hash_bytes(const void *p, size_t n)
{
    const unsigned char *b = p;
    uint64_t h = 0x9e3779b97f4a7c15ULL ^ n;
    while (n >= 8) {
        uint64_t w;
        memcpy(&w, b, 8);
        h = mix(h ^ w);
        b += 8;
        n -= 8;
    }
    uint64_t w = 0;
    memcpy(&w, b, n);
    return mix(h ^ w);
}

uint64_t index_hash_text_nocase(const char *s)
{
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (; *s; s++)
        h = (h ^ (unsigned char)tolower((unsigned char)*s)) * 0x100000001b3ULL;
    return mix(h);
}

int index_hash_find(const index_hash *h, uint64_t hash, int (*same)(const void *ctx, int index),
                    const void *ctx)
{
    if (!h->cap)
        return -1;
    size_t mask = h->cap - 1;
    for (size_t i = hash & mask;; i = (i + 1) & mask) {
        const index_hash_entry *e = &h->e[i];
        if (e->index < 0)
            return -1;
        if (e->hash == hash && same(ctx, e->index))
            return e->index;
    }
}

static void put(index_hash_entry *tab, size_t cap, uint64_t hash, int index)
{
    size_t mask = cap - 1, i = hash & mask;
    while (tab[i].index >= 0)
        i = (i + 1) & mask;
    tab[i].hash = hash;
    tab[i].index = index;
}

int index_hash_add(index_hash *h, uint64_t hash, int index)
{
    if (2 * (h->n + 1) > h->cap) {
        size_t nc = h->cap ? 2 * h->cap : 16;
        index_hash_entry *t = malloc(nc * sizeof *t);
        if (!t)
            return -1;
        for (size_t i = 0; i < nc; i++)
            t[i].index = -1;
        for (size_t i = 0; i < h->cap; i++)
            if (h->e[i].index >= 0)
                put(t, nc, h->e[i].hash, h->e[i].index);
        free(h->e);
        h->e = t;
        h->cap = nc;
    }
    put(h->e, h->cap, hash, index);
    h->n++;
    return 0;
}

void index_hash_free(index_hash *h)
{
    free(h->e);
    memset(h, 0, sizeof *h);
}
