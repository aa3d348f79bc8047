/* A minimal FMI importer for the Windows DLLs under Wine (issue 43): FMPy
 * needs a Windows Python, which is not available offline, so this program
 * does what an importing tool does with a Co-Simulation FMU, built for
 * Windows (x86_64-w64-mingw32-gcc) and for Linux (cc) from the same source,
 * so both binaries in an FMU are driven by the same calls.
 *
 *   fmu_run LIB VERSION TOKEN RESOURCES STEP_S IN_VRS OUT_VRS IN_FILE OUT_FILE
 *
 * LIB       the FMU's library (.dll / .so), loaded at run time
 * VERSION   2 or 3 (FMI 2.0 or 3.0 Co-Simulation)
 * TOKEN     the guid (2.0) or instantiationToken (3.0)
 * RESOURCES fmuResourceLocation (2.0, a file: URI) or resourcePath (3.0)
 * IN_VRS    input value references, comma separated; OUT_VRS the outputs'
 * IN_FILE   one line per step, one 16-hex-digit IEEE-754 bit pattern per input
 * OUT_FILE  per step: the worst status of the step's calls, then each output's bits
 *           (written in binary mode: the same bytes on both platforms)
 *
 * Per step k: set the inputs, doStep(k * STEP_S, STEP_S), get the outputs.
 * Values travel as bit patterns, not decimal text, so neither C runtime's
 * number formatting can differ between the two platforms. A status above
 * Warning stops the run (exit 2); the FMU's log goes to stderr. */
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2FunctionTypes.h"
#include "fmi3FunctionTypes.h"

#ifdef _WIN32
#include <windows.h>
static void *open_lib(const char *path) { return (void *)LoadLibraryA(path); }
static void *symbol(void *lib, const char *name) { return (void *)GetProcAddress((HMODULE)lib, name); }
#else
#include <dlfcn.h>
static void *open_lib(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *symbol(void *lib, const char *name) { return dlsym(lib, name); }
#endif

#define MAX_VRS 16

static void *lib;

static void *need(const char *name) {
    void *f = symbol(lib, name);
    if (!f) {
        fprintf(stderr, "fmu_run: the library does not export %s\n", name);
        exit(2);
    }
    return f;
}

static size_t parse_vrs(const char *text, unsigned int *vrs) {
    size_t n = 0;
    char *end;
    while (*text && n < MAX_VRS) {
        vrs[n++] = (unsigned int)strtoul(text, &end, 10);
        text = (*end == ',') ? end + 1 : end;
        if (end == text && *end) break;
    }
    return n;
}

static double from_bits(uint64_t bits) {
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static uint64_t to_bits(double x) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    return bits;
}

static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message) {
    (void)env;
    fprintf(stderr, "[fmi3 status %d %s] %s\n", (int)status, category ? category : "", message ? message : "");
}

static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                 fmi2String message, ...) {
    (void)env;
    (void)name;
    /* The FMUs pass finished text (no format arguments). */
    fprintf(stderr, "[fmi2 status %d %s] %s\n", (int)status, category ? category : "", message ? message : "");
}

/* Keeps the worst status; stops the run above Warning (1 in both versions). */
static int worst;
static void track(int status, const char *call, long step) {
    if (status > worst) worst = status;
    if (status > 1) {
        fprintf(stderr, "fmu_run: %s returned status %d at step %ld\n", call, status, step);
        exit(2);
    }
}

int main(int argc, char **argv) {
    if (argc != 10) {
        fprintf(stderr, "usage: fmu_run LIB VERSION TOKEN RESOURCES STEP_S IN_VRS OUT_VRS IN_FILE OUT_FILE\n");
        return 2;
    }
    int version = atoi(argv[2]);
    const char *token = argv[3], *resources = argv[4];
    double h = from_bits(strtoull(argv[5], NULL, 16));
    unsigned int in_vrs[MAX_VRS], out_vrs[MAX_VRS];
    size_t n_in = parse_vrs(argv[6], in_vrs), n_out = parse_vrs(argv[7], out_vrs);
    FILE *in = fopen(argv[8], "r"), *out = fopen(argv[9], "wb");
    if (!in || !out || n_in == 0 || n_out == 0 || !(h > 0.0) || (version != 2 && version != 3)) {
        fprintf(stderr, "fmu_run: bad arguments or files\n");
        return 2;
    }
    lib = open_lib(argv[1]);
    if (!lib) {
        fprintf(stderr, "fmu_run: cannot load %s\n", argv[1]);
        return 2;
    }

    fmi3Instance i3 = NULL;
    fmi2Component c2 = NULL;
    fmi2CallbackFunctions callbacks = {logger2, calloc, free, NULL, NULL};
    if (version == 3) {
        fmi3InstantiateCoSimulationTYPE *inst = need("fmi3InstantiateCoSimulation");
        i3 = inst("windows-run", token, resources, fmi3False, fmi3True, fmi3False, fmi3False, NULL, 0, NULL, logger3,
                  NULL);
        if (!i3) {
            fprintf(stderr, "fmu_run: fmi3InstantiateCoSimulation failed\n");
            return 2;
        }
        track(((fmi3EnterInitializationModeTYPE *)need("fmi3EnterInitializationMode"))(i3, fmi3False, 0.0, 0.0,
                                                                                       fmi3False, 0.0),
              "fmi3EnterInitializationMode", -1);
        track(((fmi3ExitInitializationModeTYPE *)need("fmi3ExitInitializationMode"))(i3),
              "fmi3ExitInitializationMode", -1);
    } else {
        fmi2InstantiateTYPE *inst = need("fmi2Instantiate");
        c2 = inst("windows-run", fmi2CoSimulation, token, resources, &callbacks, fmi2False, fmi2True);
        if (!c2) {
            fprintf(stderr, "fmu_run: fmi2Instantiate failed\n");
            return 2;
        }
        track(((fmi2SetupExperimentTYPE *)need("fmi2SetupExperiment"))(c2, fmi2False, 0.0, 0.0, fmi2False, 0.0),
              "fmi2SetupExperiment", -1);
        track(((fmi2EnterInitializationModeTYPE *)need("fmi2EnterInitializationMode"))(c2),
              "fmi2EnterInitializationMode", -1);
        track(((fmi2ExitInitializationModeTYPE *)need("fmi2ExitInitializationMode"))(c2),
              "fmi2ExitInitializationMode", -1);
    }

    double x[MAX_VRS], y[MAX_VRS];
    char line[1024];
    long k = 0;
    while (fgets(line, sizeof line, in)) {
        char *p = line, *end;
        size_t n = 0;
        while (n < n_in) {
            uint64_t bits = strtoull(p, &end, 16);
            if (end == p) break;
            x[n++] = from_bits(bits);
            p = end;
        }
        if (n == 0) continue;
        if (n != n_in) {
            fprintf(stderr, "fmu_run: line %ld has %lu values, not %lu\n", k + 1, (unsigned long)n, (unsigned long)n_in);
            return 2;
        }
        worst = 0;
        double t = (double)k * h;
        if (version == 3) {
            fmi3Boolean event, terminate, early;
            fmi3Float64 last;
            track(((fmi3SetFloat64TYPE *)need("fmi3SetFloat64"))(i3, in_vrs, n_in, x, n_in), "fmi3SetFloat64", k);
            track(((fmi3DoStepTYPE *)need("fmi3DoStep"))(i3, t, h, fmi3True, &event, &terminate, &early, &last),
                  "fmi3DoStep", k);
            track(((fmi3GetFloat64TYPE *)need("fmi3GetFloat64"))(i3, out_vrs, n_out, y, n_out), "fmi3GetFloat64",
                  k);
        } else {
            track(((fmi2SetRealTYPE *)need("fmi2SetReal"))(c2, in_vrs, n_in, x), "fmi2SetReal", k);
            track(((fmi2DoStepTYPE *)need("fmi2DoStep"))(c2, t, h, fmi2True), "fmi2DoStep", k);
            track(((fmi2GetRealTYPE *)need("fmi2GetReal"))(c2, out_vrs, n_out, y), "fmi2GetReal", k);
        }
        fprintf(out, "%d", worst);
        for (size_t j = 0; j < n_out; j++) fprintf(out, " %016" PRIx64, to_bits(y[j]));
        fprintf(out, "\n");
        k++;
    }
    if (version == 3) {
        track(((fmi3TerminateTYPE *)need("fmi3Terminate"))(i3), "fmi3Terminate", k);
        ((fmi3FreeInstanceTYPE *)need("fmi3FreeInstance"))(i3);
    } else {
        track(((fmi2TerminateTYPE *)need("fmi2Terminate"))(c2), "fmi2Terminate", k);
        ((fmi2FreeInstanceTYPE *)need("fmi2FreeInstance"))(c2);
    }
    fclose(out);
    fprintf(stderr, "fmu_run: %ld steps\n", k);
    return 0;
}
