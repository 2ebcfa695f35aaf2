/*
 * A small FMI 2.0 co-simulation host written by the project (issue 7), the way a C tool
 * would load an FMU: it reads modelDescription.xml of an extracted FMU, loads the binary of the
 * platform it was compiled for (binaries/linux64/<modelIdentifier>.so, aarch64-linux/...so,
 * win64/...dll: issue 15; dlopen or LoadLibrary), instantiates with the GUID of the
 * description and the resource location as a file: URI (on Windows with the drive letter,
 * file:///Z:/...), sets start values, runs fixed communication steps from 0 to the stop time and
 * prints every output as CSV (time first) on stdout. The FMI 2.0 types it needs are written
 * here by hand.
 *
 *   host [--run-up values|derivatives <alpha>] <extracted FMU dir> <stop time> <step size>
 *        [name=value ...]
 *   host --unload-cycles <n> <extracted FMU dir> <stop time> <step size> [name=value ...]
 *
 * --unload-cycles loads the binary, instantiates, initializes, makes one step, reads every
 * output, frees the instance and unloads the binary, n times after 5 warm-up cycles, as FMPy
 * does at the end of every simulation, and prints the heap bytes each cycle left allocated
 * (the average) instead of the CSV: the process heap's busy blocks on Windows (HeapWalk; Rust's
 * allocator there is HeapAlloc on that heap), glibc's mallinfo2 on Linux (tests/unload.rs
 * measures the same through Rust).
 *
 * --run-up drives an FMU that declares canInterpolateInputs at its elastodynamic level
 * (model.fidelity = 3) in input mode (drive.mode = 1), before the name=value assignments: the
 * shaft runs up from its start speed w0 (shaft.w after the assignments) at the constant
 * acceleration alpha, phi(t) = w0*t + alpha*t^2/2. At every communication point t, before the
 * outputs are printed and the step from t is made, the host sets shaft.phi = phi(t) and
 *   values:      shaft.w = w0 + alpha*t and shaft.a = alpha (also in initialization mode);
 *   derivatives: only fmi2SetRealInputDerivatives of shaft.phi, orders 1 and 2 (w0 + alpha*t,
 *                alpha); shaft.w and shaft.a are left to the FMU.
 * Both describe the same path inside every step. After initialization it also calls
 * fmi2GetRealOutputDerivatives once (shaft.phi's order 1): the FMU declares
 * maxOutputDerivativeOrder = 0, so the call must return fmi2Error and log one error; any other
 * status is a failure (exit 1), and this expected error does not count as one.
 *
 * Exit status 0 when every call returned fmi2OK; messages of the FMU go to stderr.
 * Build: gcc -Wall -Wextra -Werror -std=c99 -o host host.c -ldl (x86_64-w64-mingw32-gcc for
 * win64, aarch64-linux-gnu-gcc for aarch64-linux).
 */
#define _POSIX_C_SOURCE 200809L
#ifdef _WIN32
#include <windows.h>
#define PLATFORM "win64"
#define LIBRARY_EXTENSION ".dll"
typedef HMODULE Library;
#else
#include <dlfcn.h>
#include <malloc.h>
#if defined(__aarch64__)
#define PLATFORM "aarch64-linux"
#else
#define PLATFORM "linux64"
#endif
#define LIBRARY_EXTENSION ".so"
typedef void *Library;
#endif
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- FMI 2.0 types (fmi2TypesPlatform.h, fmi2FunctionTypes.h), by hand ---- */
typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef const char *fmi2String;
typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef struct {
    void (*logger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(fmi2ComponentEnvironment, fmi2Status);
    fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;
typedef fmi2Component (*Instantiate)(fmi2String, fmi2Type, fmi2String, fmi2String,
                                     const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef void (*FreeInstance)(fmi2Component);
typedef fmi2Status (*SetupExperiment)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
                                      fmi2Real);
typedef fmi2Status (*Call0)(fmi2Component);
typedef fmi2Status (*GetReal)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef fmi2Status (*GetInteger)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Integer *);
typedef fmi2Status (*SetReal)(fmi2Component, const fmi2ValueReference *, size_t, const fmi2Real *);
typedef fmi2Status (*SetInteger)(fmi2Component, const fmi2ValueReference *, size_t,
                                 const fmi2Integer *);
typedef fmi2Status (*DoStep)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);
typedef fmi2Status (*SetRealInputDerivatives)(fmi2Component, const fmi2ValueReference *, size_t,
                                              const fmi2Integer *, const fmi2Real *);
typedef fmi2Status (*GetRealOutputDerivatives)(fmi2Component, const fmi2ValueReference *, size_t,
                                               const fmi2Integer *, fmi2Real *);

/* ---- the model description, read with plain string search ---- */
enum { T_REAL, T_INTEGER, T_BOOLEAN };
typedef struct {
    char *name;
    fmi2ValueReference vr;
    int type;
    int output;
} Variable;

static char *read_file(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        s = NULL;
    }
    if (s) s[n] = '\0';
    fclose(f);
    return s;
}

/* The value of attribute `attr` inside the tag that starts at `tag` (up to its '>'). */
static char *attribute(const char *tag, const char *attr) {
    const char *end = strchr(tag, '>');
    size_t n = strlen(attr);
    for (const char *p = tag; p && end && p < end; p++) {
        p = strstr(p, attr);
        if (!p || p >= end) return NULL;
        if ((p[-1] == ' ' || p[-1] == '\n' || p[-1] == '\t') && p[n] == '=' && p[n + 1] == '"') {
            const char *v = p + n + 2, *q = strchr(v, '"');
            char *out = malloc((size_t)(q - v) + 1);
            memcpy(out, v, (size_t)(q - v));
            out[q - v] = '\0';
            return out;
        }
    }
    return NULL;
}

static int log_errors = 0;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s] %s (status %d): ", name ? name : "?", category ? category : "?",
            (int)status);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
    if (status >= fmi2Error) log_errors++;
}

/* The variable called `name` (its first n characters), or NULL. */
static Variable *lookup(Variable *vars, size_t nv, const char *name, size_t n) {
    for (size_t i = 0; i < nv; i++)
        if (strlen(vars[i].name) == n && strncmp(vars[i].name, name, n) == 0) return &vars[i];
    return NULL;
}

/* The binary at `path`, or NULL with the reason on stderr. */
static Library load(const char *path) {
#ifdef _WIN32
    Library lib = LoadLibraryA(path);
    if (!lib) fprintf(stderr, "host: LoadLibrary(%s): error %lu\n", path, GetLastError());
#else
    Library lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) fprintf(stderr, "host: %s\n", dlerror());
#endif
    return lib;
}

static void unload(Library lib) {
#ifdef _WIN32
    FreeLibrary(lib);
#else
    dlclose(lib);
#endif
}

typedef void (*Function)(void);

static Function sym(Library lib, const char *name) {
#ifdef _WIN32
    Function p = (Function)GetProcAddress(lib, name);
#else
    Function p;
    *(void **)&p = dlsym(lib, name);
#endif
    if (!p) {
        fprintf(stderr, "host: %s not exported\n", name);
        exit(2);
    }
    return p;
}

/* Bytes in use on the heap every allocator of this process shares. */
static long long heap_in_use(void) {
#ifdef _WIN32
    HANDLE heap = GetProcessHeap();
    PROCESS_HEAP_ENTRY e;
    long long n = 0;
    e.lpData = NULL;
    HeapLock(heap);
    while (HeapWalk(heap, &e))
        if (e.wFlags & PROCESS_HEAP_ENTRY_BUSY) n += (long long)e.cbData;
    HeapUnlock(heap);
    return n;
#else
    struct mallinfo2 m = mallinfo2();
    return (long long)(m.uordblks + m.hblkhd);
#endif
}

/* The resource location of the extracted FMU `dir` as a file: URI (forward slashes; on
   Windows the drive letter follows three slashes: file:///C:/...). */
static void resource_uri(const char *dir, char *uri, size_t size) {
    snprintf(uri, size, "file://%s%s/resources", dir[0] == '/' ? "" : "/", dir);
    for (char *p = uri; *p; p++)
        if (*p == '\\') *p = '/';
}

#define CHECK(call)                                                         \
    do {                                                                    \
        fmi2Status s_ = (call);                                             \
        if (s_ != fmi2OK) {                                                 \
            fprintf(stderr, "host: %s returned %d\n", #call, (int)s_);      \
            status = 1;                                                     \
            goto done;                                                      \
        }                                                                   \
    } while (0)

enum { RUN_NONE, RUN_VALUES, RUN_DERIVATIVES };

/* Loads `library`, instantiates it with `guid` and `resources`, sets the assignments
   (name=value), runs from 0 to `stop` in steps of `h` (printing every output as CSV when `print`)
   and frees the instance; unloads the library when `unload_after`. */
static int simulate(const char *library, const char *guid, const char *resources, Variable *vars,
                    size_t nv, char **assign, int nassign, int run_up, double alpha, double stop,
                    double h, int print, int unload_after) {
    Library lib = load(library);
    if (!lib) return 2;
    Instantiate instantiate = (Instantiate)sym(lib, "fmi2Instantiate");
    FreeInstance free_instance = (FreeInstance)sym(lib, "fmi2FreeInstance");
    SetupExperiment setup = (SetupExperiment)sym(lib, "fmi2SetupExperiment");
    Call0 enter = (Call0)sym(lib, "fmi2EnterInitializationMode");
    Call0 exit_init = (Call0)sym(lib, "fmi2ExitInitializationMode");
    Call0 terminate = (Call0)sym(lib, "fmi2Terminate");
    GetReal get_real = (GetReal)sym(lib, "fmi2GetReal");
    GetInteger get_integer = (GetInteger)sym(lib, "fmi2GetInteger");
    GetInteger get_boolean = (GetInteger)sym(lib, "fmi2GetBoolean");
    SetReal set_real = (SetReal)sym(lib, "fmi2SetReal");
    SetInteger set_integer = (SetInteger)sym(lib, "fmi2SetInteger");
    SetInteger set_boolean = (SetInteger)sym(lib, "fmi2SetBoolean");
    DoStep do_step = (DoStep)sym(lib, "fmi2DoStep");
    SetRealInputDerivatives set_input_derivatives =
        (SetRealInputDerivatives)sym(lib, "fmi2SetRealInputDerivatives");
    GetRealOutputDerivatives get_output_derivatives =
        (GetRealOutputDerivatives)sym(lib, "fmi2GetRealOutputDerivatives");
    Variable *phi = lookup(vars, nv, "shaft.phi", 9), *w = lookup(vars, nv, "shaft.w", 7),
             *a = lookup(vars, nv, "shaft.a", 7);

    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    int status = 0;
    fmi2Component c = instantiate("host", fmi2CoSimulation, guid, resources, &callbacks, 0, 0);
    if (!c) {
        fprintf(stderr, "host: fmi2Instantiate failed\n");
        return 1;
    }
    CHECK(setup(c, 0, 0.0, 0.0, 1, stop));
    CHECK(enter(c));
    if (run_up) {
        if (!phi || !w || !a) {
            fprintf(stderr, "host: --run-up needs shaft.phi, shaft.w and shaft.a\n");
            status = 2;
            goto done;
        }
        /* the elastodynamic level, driven by the shaft inputs */
        const char *level[] = {"model.fidelity", "drive.mode"};
        const fmi2Integer item[] = {3, 1};
        for (int k = 0; k < 2; k++) {
            Variable *v = lookup(vars, nv, level[k], strlen(level[k]));
            if (!v) {
                fprintf(stderr, "host: --run-up needs %s\n", level[k]);
                status = 2;
                goto done;
            }
            CHECK(set_integer(c, &v->vr, 1, &item[k]));
        }
    }
    for (int k = 0; k < nassign; k++) {
        char *eq = strchr(assign[k], '=');
        Variable *v = eq ? lookup(vars, nv, assign[k], (size_t)(eq - assign[k])) : NULL;
        if (!v) {
            fprintf(stderr, "host: no variable for %s\n", assign[k]);
            status = 2;
            goto done;
        }
        if (v->type == T_REAL) {
            fmi2Real x = atof(eq + 1);
            CHECK(set_real(c, &v->vr, 1, &x));
        } else {
            fmi2Integer x = atoi(eq + 1);
            CHECK((v->type == T_BOOLEAN ? set_boolean : set_integer)(c, &v->vr, 1, &x));
        }
    }
    fmi2Real w0 = 0.0;
    if (run_up) {
        CHECK(get_real(c, &w->vr, 1, &w0));
        if (run_up == RUN_VALUES) CHECK(set_real(c, &a->vr, 1, &alpha));
    }
    CHECK(exit_init(c));
    if (run_up) {
        /* refused: maxOutputDerivativeOrder is 0 (one error logged, the instance goes on) */
        const fmi2Integer order = 1;
        fmi2Real dx = -1.0;
        int errors = log_errors;
        fmi2Status s = get_output_derivatives(c, &phi->vr, 1, &order, &dx);
        if (s != fmi2Error || log_errors != errors + 1) {
            fprintf(stderr, "host: fmi2GetRealOutputDerivatives returned %d with %d error(s) "
                            "logged, expected fmi2Error (%d) with 1\n",
                    (int)s, log_errors - errors, (int)fmi2Error);
            status = 1;
            goto done;
        }
        fprintf(stderr, "host: fmi2GetRealOutputDerivatives refused (fmi2Error), as expected\n");
        log_errors = errors;
    }

    if (print) {
        printf("time");
        for (size_t i = 0; i < nv; i++)
            if (vars[i].output) printf(",%s", vars[i].name);
        printf("\n");
    }
    long steps = (long)(stop / h + 0.5);
    for (long k = 0;; k++) {
        double t = k * h;
        if (run_up) {
            /* the run-up's angle at t, and how it goes on inside the step from t */
            fmi2Real x[3] = {w0 * t + 0.5 * alpha * t * t, w0 + alpha * t, alpha};
            if (run_up == RUN_VALUES) {
                const fmi2ValueReference vr[3] = {phi->vr, w->vr, a->vr};
                CHECK(set_real(c, vr, 3, x));
            } else {
                const fmi2ValueReference vr[2] = {phi->vr, phi->vr};
                const fmi2Integer order[2] = {1, 2};
                CHECK(set_real(c, &phi->vr, 1, &x[0]));
                CHECK(set_input_derivatives(c, vr, 2, order, &x[1]));
            }
        }
        if (print) printf("%.17g", t);
        for (size_t i = 0; i < nv; i++) {
            if (!vars[i].output) continue;
            if (vars[i].type == T_REAL) {
                fmi2Real x;
                CHECK(get_real(c, &vars[i].vr, 1, &x));
                if (print) printf(",%.17g", x);
            } else {
                fmi2Integer x;
                CHECK((vars[i].type == T_BOOLEAN ? get_boolean : get_integer)(c, &vars[i].vr, 1, &x));
                if (print) printf(",%d", x);
            }
        }
        if (print) printf("\n");
        if (k == steps) break;
        /* communication points t_k = k*h, without drift; the step is t_{k+1} - t_k */
        CHECK(do_step(c, t, (k + 1) * h - t, 1));
    }
    CHECK(terminate(c));
done:
    free_instance(c);
    if (unload_after) unload(lib);
    if (log_errors && !status) status = 1;
    return status;
}

int main(int argc, char **argv) {
    int run_up = RUN_NONE;
    double alpha = 0.0;
    long cycles = 0;
    if (argc > 3 && strcmp(argv[1], "--unload-cycles") == 0) {
        cycles = atol(argv[2]);
        argv += 2;
        argc -= 2;
        if (cycles <= 0) argc = 0; /* usage */
    }
    if (argc > 3 && strcmp(argv[1], "--run-up") == 0) {
        run_up = strcmp(argv[2], "values") == 0        ? RUN_VALUES
                 : strcmp(argv[2], "derivatives") == 0 ? RUN_DERIVATIVES
                                                       : RUN_NONE;
        alpha = atof(argv[3]);
        argv += 3;
        argc -= 3;
        if (run_up == RUN_NONE) argc = 0; /* usage */
    }
    if (argc < 4) {
        fprintf(stderr, "usage: host [--run-up values|derivatives <alpha> | --unload-cycles <n>] "
                        "<extracted FMU dir> <stop time> <step size> [name=value ...]\n");
        return 2;
    }
    const char *dir = argv[1];
    double stop = atof(argv[2]), h = atof(argv[3]);
    char path[4096];
    snprintf(path, sizeof path, "%s/modelDescription.xml", dir);
    char *md = read_file(path);
    if (!md) {
        fprintf(stderr, "host: cannot read %s\n", path);
        return 2;
    }
    char *guid = attribute(strstr(md, "<fmiModelDescription"), "guid");
    const char *cs = strstr(md, "<CoSimulation");
    char *id = cs ? attribute(cs, "modelIdentifier") : NULL;
    if (!guid || !id) {
        fprintf(stderr, "host: no guid or CoSimulation modelIdentifier in %s\n", path);
        return 2;
    }

    /* every ScalarVariable: name, value reference, type, is it an output */
    size_t nv = 0, cap = 64;
    Variable *vars = malloc(cap * sizeof *vars);
    for (const char *p = strstr(md, "<ScalarVariable"); p; p = strstr(p + 1, "<ScalarVariable")) {
        if (nv == cap) vars = realloc(vars, (cap *= 2) * sizeof *vars);
        Variable *v = &vars[nv++];
        v->name = attribute(p, "name");
        char *vr = attribute(p, "valueReference"), *causality = attribute(p, "causality");
        v->vr = (fmi2ValueReference)strtoul(vr ? vr : "0", NULL, 10);
        v->output = causality && strcmp(causality, "output") == 0;
        free(vr);
        free(causality);
        const char *t = strchr(p, '>') + 1;
        while (*t == ' ' || *t == '\n' || *t == '\r' || *t == '\t') t++;
        v->type = strncmp(t, "<Real", 5) == 0 ? T_REAL
                  : strncmp(t, "<Boolean", 8) == 0 ? T_BOOLEAN
                                                   : T_INTEGER; /* Integer, Enumeration */
    }

    char library[4400], resources[4200];
    snprintf(library, sizeof library, "%s/binaries/" PLATFORM "/%s" LIBRARY_EXTENSION, dir, id);
    resource_uri(dir, resources, sizeof resources);
    int status = 0;
    if (cycles == 0) {
        status = simulate(library, guid, resources, vars, nv, argv + 4, argc - 4, run_up, alpha,
                          stop, h, 1, 0);
    } else {
        /* warm-up: the host's own one-time allocations (stdio buffers, the loader's tables) */
        long long before = 0;
        for (long k = -5; k < cycles && status == 0; k++) {
            if (k == 0) before = heap_in_use();
            status = simulate(library, guid, resources, vars, nv, argv + 4, argc - 4, RUN_NONE,
                              0.0, h, h, 0, 1);
        }
        if (status == 0)
            printf("%.1f bytes per load/unload cycle stay allocated (%ld cycles)\n",
                   (double)(heap_in_use() - before) / (double)cycles, cycles);
    }
    for (size_t i = 0; i < nv; i++) free(vars[i].name);
    free(vars);
    free(guid);
    free(id);
    free(md);
    return status;
}
