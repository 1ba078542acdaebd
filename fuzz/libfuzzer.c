/* fuzz/libfuzzer.c - libFuzzer's entry point for one target of fuzz/targets.c.
   Built by `make fuzz` (fuzz/run.sh) with clang -fsanitize=fuzzer,address,undefined
   and -DFUZZ_TARGET='"scene"' (or "ply", "pfm", "spectrum").  Each process writes
   its scratch files into its own directory under $TMPDIR. */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>
#include "../specnee.h"

int fuzz_run(const char *target, const unsigned char *data, size_t n, const char *tmpdir,
             Error *e);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t n);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t n)
{
    static char dir[512];
    Error e;
    if (!dir[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/specnee-fuzz-%s-%ld", t ? t : "/tmp", FUZZ_TARGET,
                 (long)getpid());
        mkdir(dir, 0700);
    }
    fuzz_run(FUZZ_TARGET, data, n, dir, &e);
    return 0;
}
