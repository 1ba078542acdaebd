/* fuzz/replay.c - runs saved inputs through a fuzz target (fuzz/targets.c) without
   libFuzzer: `fuzz/replay TARGET TMPDIR FILE...`.  `make test` (tests/run.sh) runs
   it on fuzz/regress/TARGET/ (every input that ever crashed a target) and on the
   seeds, in the normal build and under AddressSanitizer + UBSan.  A target that
   crashes or aborts kills this program; otherwise it prints one line per input
   (accepted, or refused with the error message) and "replay TARGET: N passed, 0
   failed". */
#include "../specnee.h"
#include <stdlib.h>
#include <string.h>

int fuzz_run(const char *target, const unsigned char *data, size_t n, const char *tmpdir,
             Error *e);

int main(int argc, char **argv)
{
    int i, passed = 0, failed = 0;
    if (argc < 3) {
        fprintf(stderr, "usage: fuzz/replay TARGET TMPDIR FILE...\n");
        return 2;
    }
    for (i = 3; i < argc; i++) {
        FILE *f = fopen(argv[i], "rb");
        unsigned char *buf = NULL;
        size_t n = 0, cap = 0;
        Error e;
        int r;
        if (!f) { printf("FAIL %s: cannot open\n", argv[i]); failed++; continue; }
        for (;;) {
            size_t got;
            if (n == cap) {
                unsigned char *nb;
                cap = cap ? 2 * cap : 4096;
                nb = (unsigned char *)realloc(buf, cap);
                if (!nb) break;
                buf = nb;
            }
            got = fread(buf + n, 1, cap - n, f);
            n += got;
            if (got == 0) break;
        }
        fclose(f);
        r = fuzz_run(argv[1], buf ? buf : (unsigned char *)"", n, argv[2], &e);
        free(buf);
        if (r < 0) {
            fprintf(stderr, "unknown target '%s' (scene, ply, pfm, spectrum)\n", argv[1]);
            return 2;
        }
        if (r) printf("ok   %s (accepted)\n", argv[i]);
        else printf("ok   %s (refused: %s)\n", argv[i], e.msg);
        passed++;
    }
    printf("replay %s: %d passed, %d failed\n", argv[1], passed, failed);
    return failed ? 1 : 0;
}
