#ifndef SPARSELENS_GLASS_FORMULA_H
#define SPARSELENS_GLASS_FORMULA_H
/* Dispersion formulas by AGF formula number (see glass.h): n at lambda (um) from the
 * coefficient array. Returns NAN for an unknown formula or a negative n^2. */
double glass_formula_eval(int formula, const double *coef, double lambda_um);
/* Number of coefficients the formula uses (for readers and writers); 0 if unknown. */
int glass_formula_ncoef(int formula);
const char *glass_formula_name(int formula);

#endif
