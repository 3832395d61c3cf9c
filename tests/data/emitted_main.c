/* A driver for a function written by --emit c (tests/cli/eval.sh, tests/cli/fit.sh): reads
 * rows "x y u v lambda" on standard input (comment lines skipped) and prints for each the
 * pass flag and the first five outputs to 17 digits, to be compared with lens-eval.
 * Compile with -DLENS_FN=the function's name. */
#include <stdio.h>

int LENS_FN(const double in[5], double out[5]);

int main(void)
{
    char line[1024];
    double in[5], out[64];
    while (fgets(line, sizeof line, stdin)) {
        if (line[0] == '#' ||
            sscanf(line, "%lf %lf %lf %lf %lf", &in[0], &in[1], &in[2], &in[3], &in[4]) != 5)
            continue;
        int p = LENS_FN(in, out);
        printf("%d %.17g %.17g %.17g %.17g %.17g\n", p, out[0], out[1], out[2], out[3], out[4]);
    }
    return 0;
}
