/*
 * Loads a panic-probe library (tests/common/probe.rs: a cdylib built with fmus/build.rs and the
 * FMUs' release profile for one platform) the way a host loads an FMU binary, and calls its
 * `int probe(int x)` with 0, 1 and 2: x > 0 panics inside the library, which must catch it and
 * return -1. Prints the three results ("0 -1 -1" when the unwinder works) on stdout.
 *
 *   probe <library>
 *
 * Portable C99 for Linux (dlopen) and Windows (LoadLibrary); cross-compiled for the platform
 * under test and run there (natively, under qemu-user or under Wine).
 */
#include <stdio.h>
#ifdef _WIN32
#include <windows.h>
#else
#include <dlfcn.h>
#endif

typedef int (*Probe)(int);

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: probe <library>\n");
        return 2;
    }
#ifdef _WIN32
    HMODULE lib = LoadLibraryA(argv[1]);
    if (!lib) {
        fprintf(stderr, "probe: LoadLibrary(%s) failed: error %lu\n", argv[1], GetLastError());
        return 2;
    }
    Probe probe = (Probe)(void (*)(void))GetProcAddress(lib, "probe");
#else
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "probe: %s\n", dlerror());
        return 2;
    }
    Probe probe;
    *(void **)&probe = dlsym(lib, "probe");
#endif
    if (!probe) {
        fprintf(stderr, "probe: no symbol `probe` in %s\n", argv[1]);
        return 2;
    }
    int a = probe(0), b = probe(1), c = probe(2);
    printf("%d %d %d\n", a, b, c);
    fflush(stdout);
#ifdef _WIN32
    FreeLibrary(lib);
#else
    dlclose(lib);
#endif
    return 0;
}
