#ifndef SPARSELENS_BASE_INDEX_HASH_H
#define SPARSELENS_BASE_INDEX_HASH_H
/* A hash index over an array the caller keeps: the table holds (hash, index) pairs and
 * the caller's `same` callback compares a key with an element. Readers use it so that
 * finding a name, a monomial or a glass again takes constant time, not a scan: a file
 * of n entries is read in time linear in n. Open addressing, at most half full. */
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint64_t hash;
    int index; /* -1: empty */
} index_hash_entry;

typedef struct {
    index_hash_entry *e;
    size_t cap, n; /* cap: 0 or a power of two */
} index_hash;

/* A 64-bit hash of n bytes; index_hash_text of a string with ASCII case folded. */
uint64_t index_hash_bytes(const void *p, size_t n);
uint64_t index_hash_text_nocase(const char *s);

/* The index of an element equal to the key (same(ctx, index) != 0 among those stored
 * with this hash), or -1. */
int index_hash_find(const index_hash *h, uint64_t hash, int (*same)(const void *ctx, int index),
                    const void *ctx);
/* Stores index under hash (duplicates are the caller's business). 0, or -1 when out of
 * memory (the table is kept as it was). */
int index_hash_add(index_hash *h, uint64_t hash, int index);
void index_hash_free(index_hash *h);

#endif
