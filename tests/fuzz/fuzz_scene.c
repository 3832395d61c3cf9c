/* libFuzzer target: the lens-render scene parser (scene_parse). The camera file it names
 * is only recorded here, not loaded.
 * needs: include/sparselens/scene.h */
#include "fuzz_common.h"
#include "sparselens/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_strdup(data, size);
    if (!text)
        return 0;
    scene_t s;
    lens_err err;
    scene_init(&s);
    if (scene_parse(text, "fuzz.scene", &s, &err) != 0)
        FUZZ_CHECK(err.msg[0] != 0 && strchr(err.msg, '\n') == NULL);
    scene_free(&s);
    free(text);
    return 0;
}
