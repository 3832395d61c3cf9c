#ifndef SPARSELENS_IMPORT_COMMON_H
#define SPARSELENS_IMPORT_COMMON_H
/* Machinery shared by the .zmx, .seq and .agf readers: whole-file text in the
 * encodings design programs write (UTF-16 with a byte-order mark, UTF-8, 8-bit),
 * line and token splitting, the "skipped: ..." note, and glass look-up across the
 * user's catalogs and the shipped one. Internal to the importers. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/glass.h"
#include "sparselens/lens.h"
#include "lens/lens_material.h"

/* Decodes data into a fresh NUL-terminated 8-bit/UTF-8 buffer of *out_len bytes (caller
 * frees). UTF-16 LE/BE with BOM, or LE without BOM when it is plainly so, become UTF-8;
 * a UTF-8 BOM is dropped; anything else is taken byte for byte. A NUL byte (or NUL
 * character) in the file stays in the buffer, for import_check_lines to name. NULL when
 * out of memory. */
char *import_decode(const char *data, size_t len, size_t *out_len);

/* -1 (err at path:line) when a line of the decoded text (len bytes) is longer than
 * LINE_MAX_BYTES (base/line_reader.h: the limit every reader states) or holds a NUL
 * byte: what the other readers say of such lines. */
int import_check_lines(const char *text, size_t len, const char *path, lens_err *err);

/* Reads a whole file or stream (at most 64 MB; path names it in messages). 0 on success. */
int import_read_file(const char *path, char **data, size_t *len, lens_err *err);
int import_read_stream(FILE *f, const char *path, char **data, size_t *len, lens_err *err);

/* A lens_read_* over a lens_parse_*: reads the whole stream f, then parses it. */
typedef int (*import_parser)(const char *data, size_t len, const char *path,
                             const lens_load_options *opt, lens_t *lens, lens_err *err);
int import_read_parse(FILE *f, const char *path, const lens_load_options *opt, lens_t *lens,
                      lens_err *err, import_parser parse);

/* Appends a zeroed element of size bytes to *array (*n used of *cap, doubling from 16)
 * and returns it; NULL (err: "FILE:LINE: out of memory") when memory runs out, the
 * array kept. */
void *import_push(void **array, size_t *cap, size_t *n, size_t size, const char *path,
                  long line, lens_err *err);

/* True when any of tok[from..n) is a non-zero number (a tilt, a decentre, a factor). */
int import_any_nonzero(char **tok, int n, int from);

/* Appends the numbers among tok[1..n) to dst[*count..max), passing over words that are
 * not numbers (lists of wavelengths or fields). Returns how many numbers did not fit,
 * zeros (padding) not counted, for the caller's note: nothing is dropped silently. */
int import_numbers(char **tok, int n, double *dst, int *count, int max);

/* Next line of a decoded buffer, split in place (\n, \r\n or \r); NULL at the end. */
typedef struct {
    char *p;
    long line;
} import_lines;
char *import_next_line(import_lines *it);

/* Splits a line in place into tokens at blanks, storing the first max in tok. Text in
 * double or single quotes is one token, quotes removed. Returns the number of tokens on
 * the line, which may be more than max: the caller says what it does with the rest. */
int import_tokens(char *line, char **tok, int max);

/* When line's first word is keyword (any case), the rest of the line after the blanks
 * that follow it; else NULL. For values that are free text, blanks included. */
const char *import_rest_after(const char *line, const char *keyword);

/* Copies name into dst (cap bytes): 0, or -1 with "FILE:LINE: WHAT 'NAME...' is longer
 * than N characters" (a glass name is never cut: a cut one would find another glass). */
int import_copy_name(char *dst, size_t cap, const char *name, const char *what,
                     const char *path, long line, lens_err *err);

/* Sets lens->name; a name too long for it is shortened with "..." and the full length
 * said in a note, never cut silently. */
void import_set_name(lens_t *lens, const char *name);

/* Case-insensitive string equality (keywords are upper case in files, but not always). */
int import_eq(const char *a, const char *b);
/* import_eq against any of words (a NULL-terminated list). */
int import_eq_any(const char *a, const char *const *words);

/* Things read but not modelled, counted by a human-readable label, for the notes. */
#define IMPORT_MAX_SKIPS 24
#define IMPORT_SKIP_LABEL 96 /* longer than every fixed label; file words are shortened */
typedef struct {
    char label[IMPORT_MAX_SKIPS][IMPORT_SKIP_LABEL];
    int count[IMPORT_MAX_SKIPS];
    int n;
} import_skips;
void import_skip(import_skips *sk, const char *label);
/* import_skip of "what WORD", a word from the file shortened to 40 characters with "...". */
void import_skip_word(import_skips *sk, const char *what, const char *word);
/* Appends "skipped: a (2), b" to lens->notes (nothing when there is nothing). */
void import_skips_note(const import_skips *sk, lens_t *lens);

/* What both design-file parsers keep about the whole system while they read. */
typedef struct {
    const char *path;  /* for messages */
    lens_t *lens;      /* being built */
    import_skips skips;
    double unit;       /* mm per length unit of the file */
    double epd;        /* entrance pupil diameter, file units; NAN if not given */
    double fno;        /* f-number; NAN if not given */
    int inf_words;     /* import_number reads INF and INFINITY (import_format's) */
} import_system;

/* tok[i] (of n tokens) as a number into *v. -1 with "FILE:LINE: KEY: expected a
 * number, found 'X'" (KEY = tok[0]; "end of line" when there is no tok[i]). */
int import_number(const import_system *sys, char **tok, int n, int i, long line, double *v,
                  lens_err *err);

/* The start of every design-file parser: *lens emptied, lens->path = path, lens->source =
 * "PROGRAM file BASENAME", *sys set for it (mm, no aperture yet), and data decoded
 * (import_decode) into the returned text, which the caller frees. NULL (err set) when out
 * of memory. */
char *import_begin(const char *data, size_t len, const char *path, const char *program,
                   lens_t *lens, import_system *sys, lens_err *err);

/* One design-file format for import_parse: the program that writes it (for lens->source),
 * whether import_number reads INF and INFINITY, the size of the format's state (an
 * import_system first, then the format's own), how the decoded text is read into the
 * state, how the lens is built from it, and what frees the arrays the state holds. */
typedef struct {
    const char *program;
    int inf_words;
    size_t state_size;
    int (*read)(void *state, char *text, lens_err *err);
    int (*build)(void *state, const lens_load_options *opt, lens_err *err);
    void (*free)(void *state);
} import_format;

/* Every design-file parse: a zeroed state, import_begin into its import_system,
 * fmt->read over the text, fmt->build; the state and the text freed, and *lens emptied
 * on failure. 0, or -1 with err set. */
int import_parse(const char *data, size_t len, const char *path, const lens_load_options *opt,
                 lens_t *lens, const import_format *fmt, lens_err *err);

/* The notes "fields KIND: y1 y2 (x3,y3) ..." (x may be NULL: fields along y only; an
 * x of 0 is not written) and "wavelengths (um): w1 w2 (primary) ...", wave[i] / per_um
 * in micrometres, primary counted from 1 (0: none). Nothing when n is 0. */
void import_fields_note(lens_t *lens, const char *kind, const double *x, int nx,
                        const double *y, int n);
void import_waves_note(lens_t *lens, const double *wave, int n, double per_um, int primary);

/* Radius in mm of a curvature c given per lens unit (unit mm long); INFINITY for c = 0.
 * Of the decimal radii whose reciprocal is c exactly, the shortest: a file written from
 * R = -435.7604 stores c = 1/R, and this gives back -435.7604, not -435.76040000000006. */
double import_radius(double c, double unit);

/* Makes the name, source and each note line writable and readable back unchanged in
 * the native format's header: control characters become '?', end blanks go. */
void import_clean_text(lens_t *lens);

/* The system aperture of a design file, applied to a finished lens: the stop's
 * semi-diameter is scaled so that the paraxial f-number (d line, object at infinity) is
 * fnumber, or efl / epd_mm when fnumber is 0 (design programs derive the stop size from
 * these, so the file's stop semi-diameter may be stale). hard: the stop's semi-diameter
 * is a clear aperture the file sets (Zemax CLAP, CODE V CIR), which is never enlarged.
 * Sets lens->fnumber (the nominal one); notes a change of the stop, or a kept hard
 * aperture; -1 (err) when the stop surface cannot be that large. */
int import_set_aperture(lens_t *lens, double fnumber, double epd_mm, const char *what,
                        int hard, lens_err *err);

/* The steps both design-file readers end with: the skipped-keyword note, cleaned
 * header text, lens_finish, then the system aperture (an f-number when fnumber > 0,
 * else an entrance pupil when epd_mm > 0; fno_name/epd_name are the file's keywords,
 * for the notes). */
int import_finish(lens_t *lens, const import_skips *skips, double fnumber, const char *fno_name,
                  double epd_mm, const char *epd_name, int hard, lens_err *err);

/* Glass look-up through lens_import.h's material_ctx: the extra catalogs
 * (opt->catalogs), glass.catalog beside the lens, then the shipped one. */
typedef struct {
    const lens_load_options *opt;
    material_ctx m;      /* the catalogs, in lens_load's order, read on first use */
    char fallbacks[200]; /* glasses that fell back to nd/Vd, for the note */
    char choices[400];   /* old names and vendor choices made, for the note */
    char maker_catalogs[100]; /* catalogs the file names (Zemax GCAT), for the message */
} import_glass_ctx;

void import_glass_init(import_glass_ctx *g, const lens_load_options *opt, const char *lens_path);
void import_glass_free(import_glass_ctx *g);

/* Resolves a named glass into s->medium and s->material. nd, vd: the values the file
 * gives beside the name (NAN when none), used only for the nd/Vd fallback, and never
 * when they are a catalog glass's round placeholders (1.5/40). Tries the name as given,
 * then case-insensitively without '-', '_' and blanks (CODE V writes NBK7 for N-BK7); a
 * trailing "_VENDOR" or ".VENDOR" selects that vendor's glass. A name several vendors
 * sell is the first vendor's in catalog order (the user's catalogs, then SCHOTT OHARA
 * HOYA HIKARI CDGM SUMITA PLASTIC), an old name is its successor (BK7: N-BK7), each
 * with a note; a glass whose formula contradicts its n_d is an error naming it. */
int import_glass_lookup(import_glass_ctx *g, const char *name, double nd, double vd,
                        const char *file, long line, lens_surface *s, lens_err *err);

/* A model glass from n_d and V_d (vd 0 or not finite: a bare index) into s->medium and
 * s->material; -1 (err at file:line) when glass_check_ndvd refuses them. */
int import_glass_model(lens_surface *s, double nd, double vd, const char *file, long line,
                       lens_err *err);

/* The largest of lens->field_x/y's fields (hypot of x and y), in its kind's unit. */
double import_top_field(const lens_t *lens);

/* Sizes the semi-diameter of each lens surface i with missing[i] from the paraxial beam
 * of the top field (lens->field_kind, fields; an angle, or an image height through the
 * focal length; the axial beam otherwise) at the aperture (entrance pupil epd_mm, else
 * f-number fno): |marginal| + |chief| height at the surface, what the unvignetted beam
 * needs and no more. key names the file's keyword (DIAM, CIR) in the note and the error,
 * aperture_keys its aperture keywords ("EPD or FNO") when it gives neither. 0, or -1 with err set. */
int import_size_apertures(lens_t *lens, const int *missing, double epd_mm, double fno,
                          const char *key, const char *aperture_keys, lens_err *err);

/* A plane stop the file puts on the vertex of the next surface when that surface curves
 * towards it (a stop in front of a concave face): the stop plane and the face cross
 * inside the stop, which no tracer can follow. The stop moves in front by the face's sag
 * at the stop's rim, its ring resting on the face (the gap in front shrinks as much), and
 * a note says so. Nothing else changes; import_finish calls it. */
void import_seat_stop(lens_t *lens);

/* Copies the fields (kind, x may be NULL) and wavelengths (um, weights may be NULL:
 * all 1; primary 1-based, 0 none) a design file gives into the lens. -1 (err at path)
 * when there are more than LENS_MAX_FIELDS or LENS_MAX_WAVES. */
int import_set_fields(lens_t *lens, lens_field_kind kind, const double *x, int nx,
                      const double *y, int n, lens_err *err);
int import_set_waves(lens_t *lens, const double *um, const double *weight, int n, int primary,
                     lens_err *err);

/* Appends the fallbacks (if any) to the notes. */
void import_glass_note(const import_glass_ctx *g, lens_t *lens);

#endif
