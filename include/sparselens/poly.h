#ifndef SPARSELENS_POLY_H
#define SPARSELENS_POLY_H
/* Adaptive sparse polynomial systems (man 5 lens-poly): per output a sparse polynomial
 * in scaled inputs, optionally one system per part of a partition of the ray space.
 * This header is the interface other modules (spot, distort, render) rely on. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct poly_system poly_system;

int poly_read(const char *path, poly_system **sys, lens_err *err);
int poly_write(FILE *f, const poly_system *sys);
void poly_free(poly_system *sys);

const char *poly_lens_name(const poly_system *sys); /* the lens it was fitted to */
const char *poly_lens_path(const poly_system *sys); /* as recorded, may be "" */
/* The lens file of the system read from poly_path, into buf: the recorded lens-path as it
 * is (absolute, or from the working directory), else relative to the .poly file's
 * directory, else, when find is given, find(lens-path) (lens_find_file: a lens named by
 * its short name, `lens-trace fisheye-ii`, is looked up as the commands look it up).
 * -1 with err naming the lens and the path when none is readable. */
int poly_find_lens_file(const poly_system *sys, const char *poly_path,
                        int (*find)(const char *name, char *buf, size_t n), char *buf,
                        size_t len, lens_err *err);
/* Whether sys belongs to the lens named lens_name, read from lens_path (may be NULL): it
 * does when the lens name it records is that name or the lens file's base name, or the
 * lens file it records has the lens file's base name, or it records no lens ("" or
 * "unknown"). NULL if so; else the reason ("the system was fitted to 'X' (path), not to
 * this lens 'Y'") in buf. The commands warn with it, lens_camera_new refuses. */
const char *poly_lens_mismatch(const poly_system *sys, const char *lens_name,
                               const char *lens_path, char *buf, size_t len);
int poly_ninputs(const poly_system *sys);
int poly_noutputs(const poly_system *sys);
const char *poly_input_name(const poly_system *sys, int i);
const char *poly_output_name(const poly_system *sys, int i);
int poly_input_index(const poly_system *sys, const char *name);  /* -1 if absent */
int poly_output_index(const poly_system *sys, const char *name); /* -1 if absent */

/* Evaluation never changes the system: any number of threads may evaluate one system
 * at once. All these functions give bit-identical outputs (and the emitted C too), on
 * any x86-64 instruction set (no FMA contraction anywhere), except poly_eval and
 * poly_eval_part where AVX-512 runs one ray in vectors (another order of additions,
 * fused multiply-adds): the same values to rounding (1e-12 relative), the pass flag
 * from them (so it may differ on a pass circle's very edge).
 * Evaluates all outputs at in[ninputs] (the system's input order, unscaled units).
 * Returns 1 if the system says the ray passes the lens, 0 if not (out still filled). */
int poly_eval(const poly_system *sys, const double *in, double *out);
/* Outputs and their partial derivatives: jac[o * ninputs + i] = d out_o / d in_i. */
int poly_eval_jacobian(const poly_system *sys, const double *in, double *out, double *jac);
/* poly_eval_jacobian of outputs outputs[0 .. nsel - 1] alone, the same values: out[nsel],
 * jac nsel x ninputs (jac[j * ninputs + i] = d out_{outputs[j]} / d in_i); no pass test
 * (the other outputs, the passage's, are not computed). Returns 0, or -1 (and writes
 * nothing) for a negative nsel or an output out of range. */
int poly_eval_jacobian_outputs(const poly_system *sys, const double *in, int nsel,
                               const int *outputs, double *out, double *jac);
/* count rays; in row-major count x ninputs, out count x noutputs; pass may be NULL.
 * Several times faster per ray than poly_eval (rays go through in vector blocks):
 * use it wherever rays come in bulk. */
void poly_eval_batch(const poly_system *sys, size_t count, const double *in, double *out,
                     unsigned char *pass);
/* poly_eval_batch writing only outputs outputs[0 .. nsel - 1], in that order: out is
 * count x nsel (nsel may be 0: the pass flags alone). The values and pass flags are
 * poly_eval_batch's, bit for bit. The outputs a caller does not ask for cost no stores;
 * without pass (NULL) they are not computed either, while the pass test needs them
 * all (a system's passage outputs: its stop and rim hit points). Returns 0, or -1 (and
 * writes nothing) for a negative nsel or an output out of range. */
int poly_eval_batch_outputs(const poly_system *sys, size_t count, const double *in, int nsel,
                            const int *outputs, double *out, unsigned char *pass);
/* The Jacobian of count rays (poly_eval_jacobian's values to 1e-12 relative: with
 * AVX-512 its sums use fused multiply-adds): jac is count x (noutputs x ninputs), row r
 * holding d out_o / d in_i at [o * ninputs + i]. */
void poly_eval_jacobian_batch(const poly_system *sys, size_t count, const double *in,
                              double *jac);
/* poly_eval_jacobian_batch for outputs outputs[0 .. nsel - 1] alone: jac is count x
 * (nsel x ninputs), row r holding d out_{outputs[j]} / d in_i at [j * ninputs + i], the
 * same values; the other outputs' derivatives are not computed (a renderer's or a
 * solver's four outer-pupil outputs of a system with passage outputs: a fraction of the
 * work). Returns 0, or -1 (and writes nothing) for a negative nsel or an output out of
 * range. */
int poly_eval_jacobian_batch_outputs(const poly_system *sys, size_t count, const double *in,
                                     int nsel, const int *outputs, double *jac);
/* Evaluates part `part` whatever the radius of in (to compare parts at a boundary);
 * returns the pass flag as poly_eval does. */
int poly_eval_part(const poly_system *sys, int part, const double *in, double *out);
/* 1 when in lies inside the input ranges seen in training (extrapolation check). */
int poly_in_domain(const poly_system *sys, const double *in);
/* 1 when the sensor point (x, y) mm at lambda um (NAN: any) lies inside what the system
 * was fitted over: for a meridional system the disc of the training sensor's corner
 * radius (it sees only the radius), else the rectangle of its x and y ranges, and the
 * training wavelengths; a system recording no such range is taken at its word. 0
 * outside, with why (n bytes) saying where the point lies and where the domain ends. */
int poly_sensor_in_domain(const poly_system *sys, double x, double y, double lambda, char *why,
                          size_t n);

/* Building a system (lens-fit, tests). Inputs are scaled before the monomials are
 * formed: s_i = (in_i - offset_i) / scale_i; coefficients multiply monomials of s.
 * A system has one or more parts; part p applies where the sensor radius
 * sqrt(x^2 + y^2) (inputs named x and y) lies in [rmin, rmax); a single part spans
 * [0, INFINITY). The passage test: the ray passes when every pass circle holds,
 * out_a^2 + out_b^2 <= radius^2 (the front element and the stop, for example), on the
 * outputs in the system's frame, before a turned pair turns back (the same length). */
poly_system *poly_new(const char *lens_name, int ninputs, const char *const *inputs,
                      int noutputs, const char *const *outputs);
void poly_set_lens_path(poly_system *sys, const char *path);
void poly_set_scaling(poly_system *sys, int input, double offset, double scale);
void poly_set_domain(poly_system *sys, int input, double lo, double hi);
int poly_add_part(poly_system *sys, double rmin, double rmax); /* returns part index */
int poly_add_term(poly_system *sys, int part, int output, const int *exponents, double coef);
int poly_add_pass_circle(poly_system *sys, int out_a, int out_b, double radius);
/* A copy of sys with the outputs o where keep[o] != 0 (NULL: all), in their order: the
 * inputs, scaling, domain, frame, transforms, parts, their terms, the pass circles on
 * two kept outputs, the lens path and the meta lines (but fit_NAME and part_jump_NAME
 * of the outputs left out). NULL when out of memory or keep keeps no output. */
poly_system *poly_copy_outputs(const poly_system *sys, const unsigned char *keep);
/* Free-form "key value" metadata lines kept in the file (fit flags, errors). */
void poly_set_meta(poly_system *sys, const char *key, const char *value);
const char *poly_get_meta(const poly_system *sys, const char *key);

/* Builder details. poly_new returns NULL on bad arguments (no inputs or outputs, a
 * name that is empty, holds whitespace or '#', or repeats, more than POLY_MAX_INPUTS
 * inputs or POLY_MAX_OUTPUTS outputs). A new system has no
 * parts: call poly_add_part(sys, 0, INFINITY) for one part over the whole sensor.
 * Scaling defaults to offset 0, scale 1; the domain to (-inf, inf).
 * poly_add_part returns -1 if rmin < 0, rmax <= rmin, the range overlaps a part, or the
 * system has POLY_MAX_PARTS parts already;
 * parts with rmin > 0 need inputs named x and y.
 * poly_add_term returns 0, or -1 for a bad part or output, a negative exponent, a total
 * degree past POLY_MAX_DEGREE, a non-finite coefficient, or a monomial the output
 * already has. Terms are evaluated and written in the order they were added.
 * poly_add_pass_circle returns 0, or -1 for a bad output or radius. */
#define POLY_MAX_DEGREE 24
/* Inputs and outputs a system may have (a sample file holds at most 64 columns), and
 * radial parts (lens-fit --parts stops at 64): they bound what one part costs, and the
 * memory a .poly file can ask for (man 5 lens-poly). */
#define POLY_MAX_INPUTS 64
#define POLY_MAX_OUTPUTS 64
#define POLY_MAX_PARTS 64

/* Around the polynomial (man 5 lens-poly, "frame" and "transform"). A rotationally
 * symmetric lens is described with one input fewer in its meridional frame: each ray
 * is rotated about the axis so that its sensor point lies on +x (inputs x, y, u, v
 * become r, 0, u', v'), the polynomials give the outputs in that frame, and output
 * pairs ..._x/..._y and ..._u/..._v are rotated back. A transform replaces an input
 * by a function of it before the scaling (inverse-square: 1 / in^2, for the
 * wavelength: glass dispersion is close to linear in it). */
enum { POLY_FRAME_NONE = 0, POLY_FRAME_MERIDIONAL = 1 };
enum { POLY_XFORM_IDENTITY = 0, POLY_XFORM_INVERSE_SQUARE = 1 };
/* 0, or -1 for an unknown frame, or a meridional frame without inputs x, y, u, v, or with
 * an output ..._x, ..._y, ..._u or ..._v whose partner is missing. */
int poly_set_frame(poly_system *sys, int frame);
int poly_get_frame(const poly_system *sys);
/* Output o computed outside the frame (plain = 1: at the inputs as given, through their
 * transforms only; for direction components that do not turn with the ray, like the
 * outer-pupil tangent frame's u, v). Pairs must agree. 0, or -1 without a frame, for a
 * bad output, or when the partner differs after this call: set both, then check with
 * poly_frame_check. */
int poly_set_output_plain(poly_system *sys, int output, int plain);
int poly_get_output_plain(const poly_system *sys, int output);
int poly_frame_check(const poly_system *sys); /* 0: every pair in or out together */
int poly_set_transform(poly_system *sys, int input, int xform); /* 0, or -1 */
int poly_get_transform(const poly_system *sys, int input);
const char *poly_frame_name(int frame);   /* "none", "meridional"; NULL if unknown */
const char *poly_xform_name(int xform);   /* "identity", "inverse-square"; NULL if unknown */
int poly_frame_parse(const char *name);   /* -1 if unknown */
/* The steps around the core alone (for fitters): the raw inputs in[ninputs] to the
 * polynomials' inputs t[ninputs] (rotated into the frame, then transformed; scaling
 * not applied), with the rotation cs[2] = (cos, sin) of the ray ((1, 0) without a
 * frame); poly_frame_out rotates frame outputs back in place, poly_frame_out_inverse
 * rotates outputs into the frame. */
void poly_frame_in(const poly_system *sys, const double *in, double *t, double *cs);
void poly_frame_out(const poly_system *sys, const double *cs, double *out);
void poly_frame_out_inverse(const poly_system *sys, const double *cs, double *out);
int poly_xform_parse(const char *name);   /* -1 if unknown */

/* Reading a system back (for reports, fitters and the emitter). */
int poly_nparts(const poly_system *sys);
void poly_part_range(const poly_system *sys, int part, double *rmin, double *rmax);
int poly_nterms(const poly_system *sys, int part, int output);
/* exponents[ninputs] and the coefficient of term t (in add order). */
void poly_get_term(const poly_system *sys, int part, int output, int t, int *exponents,
                   double *coef);
void poly_get_scaling(const poly_system *sys, int input, double *offset, double *scale);
void poly_get_domain(const poly_system *sys, int input, double *lo, double *hi);
int poly_npass_circles(const poly_system *sys);
void poly_get_pass_circle(const poly_system *sys, int c, int *out_a, int *out_b,
                          double *radius);
int poly_nmeta(const poly_system *sys);
const char *poly_meta_key(const poly_system *sys, int i);
int poly_max_degree(const poly_system *sys, int output); /* over all parts */
/* The part evaluation uses for in[] (by sensor radius; the nearest part outside all). */
int poly_part_of(const poly_system *sys, const double *in);
/* Distinct monomials per ray that evaluation computes (for reports and benchmarks). */
int poly_nmonomials(const poly_system *sys, int part);

/* Reads a system from an open stream; name is used in error messages. */
int poly_read_stream(FILE *f, const char *name, poly_system **sys, lens_err *err);

/* Writes a C function
 *   int func_name(const double in[ninputs], double out[noutputs])
 * that evaluates sys exactly as poly_eval does (same scaling, part selection, products
 * and summation order) and returns the same pass flag, and
 *   void func_name_batch(size_t n, const double *in, double *out, unsigned char *pass)
 * with the same values for n rays (rows), written as loops over blocks of 8 rays that
 * compilers vectorise (one-part systems; several parts go ray by ray). Compiles as C11
 * or C++ on its own (includes <math.h>, <stddef.h>), the functions with C linkage; every
 * external symbol begins with func_name. Names from the system reach only its comments,
 * through text_c_comment (escape.h). Returns 0, or -1 on a bad name or write error. */
int poly_emit_c(FILE *f, const poly_system *sys, const char *func_name);
/* The header of poly_emit_c's file: its two declarations, extern "C" for C++. */
int poly_emit_c_header(FILE *f, const poly_system *sys, const char *func_name);

/* 1 when name can name poly_emit_c's function (text_c_prefix_ok, escape.h). */
int poly_c_name_ok(const char *name);
/* 0 when it can; else -1 and "--name: ... " with the reason in err. */
int poly_c_name_check(const char *name, lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
