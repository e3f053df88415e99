/* Runs a fuzz harness's LLVMFuzzerTestOneInput on files, without libFuzzer,
 * so that any compiler can replay the corpus and the regression inputs.
 *   usage: replay_TARGET FILE_OR_FOLDER...   (folders: every file in them)
 * Exits 0 when every input ran (a crash or abort ends the process with its
 * signal), 1 when an input cannot be read or nothing was given. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = NULL;
    long n;
    int ok = 0;

    if (f && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 &&
        fseek(f, 0, SEEK_SET) == 0 && (buf = malloc((size_t)n + 1)) &&
        fread(buf, 1, (size_t)n, f) == (size_t)n) {
        LLVMFuzzerTestOneInput(buf, (size_t)n);
        ok = 1;
    }
    if (!ok)
        fprintf(stderr, "replay: %s: cannot read\n", path);
    free(buf);
    if (f)
        fclose(f);
    return ok;
}

int main(int argc, char **argv)
{
    size_t count = 0;
    int ok = argc > 1;

    for (int i = 1; i < argc; ++i) {
        struct stat sb;
        DIR *d;
        struct dirent *e;
        if (stat(argv[i], &sb) != 0 || !S_ISDIR(sb.st_mode)) {
            ok &= run_file(argv[i]);
            ++count;
            continue;
        }
        if (!(d = opendir(argv[i]))) {
            fprintf(stderr, "replay: %s: cannot open the folder\n", argv[i]);
            ok = 0;
            continue;
        }
        while ((e = readdir(d))) {
            char path[4096];
            if (e->d_name[0] == '.')
                continue;
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            ok &= run_file(path);
            ++count;
        }
        closedir(d);
    }
    printf("replay: %zu input(s) %s\n", count, ok ? "ran" : "could not all be read");
    return ok ? 0 : 1;
}
