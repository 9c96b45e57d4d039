/* Our small FMI framework, shared by the FMI 2.0 and FMI 3.0 API layers.
 *
 * It owns the instance, enforces the legal call order with one allowed-state
 * mask per function (FW_ALLOWED in framework.c), checks and clamps values,
 * sub-steps the model on a 1 ms grid counted by an integer (with a shorter last
 * sub-step for a communication point between grid points) and reports through the
 * importer's logger. Status codes have the same values in FMI 2 and FMI 3. */
#ifndef PLANT_FRAMEWORK_H
#define PLANT_FRAMEWORK_H

#include <stdbool.h>
#include "model.h"

/* Only the FMI functions are exported; the plant's own symbols stay inside the library,
 * whoever builds it (our cmake build also sets hidden visibility; fmpy's does not). */
#if defined(__GNUC__)
#pragma GCC visibility push(hidden)
#endif

typedef enum { FW_OK = 0, FW_WARNING = 1, FW_DISCARD = 2, FW_ERROR = 3, FW_FATAL = 4 } FwStatus;

typedef enum {
    FW_INSTANTIATED = 1 << 0,
    FW_INITIALIZATION = 1 << 1,
    FW_STEP = 1 << 2,
    FW_TERMINATED = 1 << 3,
    FW_FAILED = 1 << 4
} FwState;

typedef enum {
    FW_FN_SETUP_EXPERIMENT,
    FW_FN_ENTER_INIT,
    FW_FN_EXIT_INIT,
    FW_FN_DO_STEP,
    FW_FN_TERMINATE,
    FW_FN_RESET,
    FW_FN_GET,
    FW_FN_SET_INPUT,
    FW_FN_SET_PARAMETER,
    FW_FN_COUNT
} FwFunction;

/* The importer's logging callback, stored untyped; the API layer casts it back. */
typedef void (*FwCallback)(void);

struct FwInstance;
/* Delivers one finished message through the importer's logger. */
typedef void (*FwLogFn)(const struct FwInstance *inst, FwStatus status, const char *category,
                        const char *message);

typedef struct FwInstance {
    FwState state;
    char *name;
    void *env;               /* the importer's instance environment */
    FwCallback logger;       /* the importer's logger, for log_fn */
    FwLogFn log_fn;
    bool logging_on;
    double start_time_s;
    long long steps;           /* whole internal steps since start */
    double frac_s;             /* into the current grid cell, [0, h); time = start + steps * h + frac */
    bool clamped[PLANT_VR_CAP];
    PlantModel model;
} FwInstance;

typedef struct {
    const char *name;
    const char *token;
    FwLogFn log_fn;
    FwCallback logger;
    void *env;
    bool logging_on;
} FwInstantiation;

FwInstance *fw_instantiate(const FwInstantiation *how);
void fw_free(FwInstance *inst);
void fw_log(FwInstance *inst, FwStatus status, const char *category, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* True if fn may be called now; otherwise logs an error naming api_name. */
bool fw_allowed(FwInstance *inst, FwFunction fn, const char *api_name);
FwStatus fw_unsupported(FwInstance *inst, const char *api_name);

FwStatus fw_setup_experiment(FwInstance *inst, double start_time_s);
FwStatus fw_enter_initialization(FwInstance *inst);
FwStatus fw_exit_initialization(FwInstance *inst);
FwStatus fw_do_step(FwInstance *inst, double t_s, double h_s, double *last_time_s);
FwStatus fw_terminate(FwInstance *inst);
FwStatus fw_reset(FwInstance *inst);

FwStatus fw_get_real(FwInstance *inst, unsigned vr, double *value);
FwStatus fw_set_real(FwInstance *inst, unsigned vr, double value);
FwStatus fw_get_bool(FwInstance *inst, unsigned vr, bool *value);
FwStatus fw_set_bool(FwInstance *inst, unsigned vr, bool value);

static inline FwStatus fw_worst(FwStatus a, FwStatus b) {
    return a > b ? a : b;
}

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif
