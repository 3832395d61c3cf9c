/* Whether a fit's samples carried what passage needs (fit.h: fit_passage_gap). */
#include <stdio.h>
#include <string.h>

#include "sparselens/fit.h"

const char *fit_passage_gap(const char *note, int nout, const char *const *outputs,
                            int unfitted, size_t blocked, char *buf, size_t len)
{
    int stop = 0;
    for (int o = 0; o < nout; o++)
        stop |= strcmp(outputs[o], "ap_x") == 0;
    if (!stop)
        snprintf(buf, len, "the stop is not modelled (its hit is not among the outputs)");
    else if (unfitted)
        snprintf(buf, len, "%d passage column%s of the samples not among the outputs", unfitted,
                 unfitted == 1 ? "" : "s");
    else if (!note || strncmp(note, "full", 4) != 0)
        snprintf(buf, len, "the samples do not say that their clip surfaces were found over "
                           "the full ray space (lens-trace writes '# passage: full')");
    else if (blocked == 0)
        snprintf(buf, len, "no blocked rays in the samples: the fit saw one side of each rim");
    else
        return NULL;
    return buf;
}
