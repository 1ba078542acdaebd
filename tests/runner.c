/* tests/runner.c - runs every test table of tests/tables.h; `tests/runner
   [substring ...]` runs only the tests whose names contain one of the substrings
   (tools/mutants.sh passes a list); `tests/runner --tables` prints the tables'
   names, one a line, and runs nothing (tests/run.sh checks that every
   tests/test_*.c is among them).  Ends with the line "unit: N passed, N failed"
   and exits non-zero on failure. */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

void test_failf(T *t, const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    int n;
    if (t->failed++) return;
    n = snprintf(t->msg, sizeof t->msg, "%s:%d: ", file, line);
    va_start(ap, fmt);
    vsnprintf(t->msg + n, sizeof t->msg - (size_t)n, fmt, ap);
    va_end(ap);
}

const char *test_path(T *t, const char *name)
{
    static char buf[8][1024];
    static int slot;
    char *p = buf[slot++ & 7];
    snprintf(p, 1024, "%s/%s", t->tmpdir, name);
    return p;
}

const char *test_write_file(T *t, const char *name, const char *text)
{
    const char *p = test_path(t, name);
    FILE *f = fopen(p, "wb");
    if (!f) return p;
    fputs(text, f);
    fclose(f);
    return p;
}

double test_scale(void)
{
    const char *e = getenv("SPECNEE_TEST_SCALE");
    double v = e ? atof(e) : 1.0;
    return v > 0.0 ? v : 1.0;
}

int test_scaled(int n, int lo)
{
    int v = (int)(n * test_scale() + 0.5);
    return v < lo ? lo : v;
}

static const struct { const char *name; const TestCase *cases; } tables[] = {
#define TEST_TABLE(x) { #x, tests_##x },
#include "tables.h"
#undef TEST_TABLE
    { NULL, NULL }
};

int main(int argc, char **argv)
{
    const char *tmp = getenv("SPECNEE_TEST_TMP");
    int passed = 0, failed = 0, i, j;
    char cmd[512];
    if (argc == 2 && strcmp(argv[1], "--tables") == 0) {
        for (i = 0; tables[i].name; i++) printf("%s\n", tables[i].name);
        return 0;
    }
    if (!tmp) tmp = "tests/tmp";
    snprintf(cmd, sizeof cmd, "mkdir -p %s", tmp);
    if (system(cmd) != 0) { fprintf(stderr, "cannot create %s\n", tmp); return 2; }
    for (i = 0; tables[i].cases; i++) {
        for (j = 0; tables[i].cases[j].name; j++) {
            T t;
            clock_t c0 = clock();
            int k, wanted = argc < 2;
            for (k = 1; k < argc && !wanted; k++) wanted = strstr(tables[i].cases[j].name, argv[k]) != NULL;
            if (!wanted) continue;
            memset(&t, 0, sizeof t);
            t.tmpdir = tmp;
            tables[i].cases[j].fn(&t);
            if (t.failed) {
                printf("FAIL %s: %s\n", tables[i].cases[j].name, t.msg);
                failed++;
            } else {
                printf("ok   %s (%.2fs)\n", tables[i].cases[j].name,
                       (double)(clock() - c0) / CLOCKS_PER_SEC);
                passed++;
            }
            fflush(stdout);
        }
    }
    printf("unit: %d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
