/* Instance lifecycle, the call-order state machine, logging and doStep. */
#include "framework.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* PLANT_TOKEN, the GUID / instantiation token: written by fmu_plant/build.py next to the
 * sources it compiles and ships in the FMU's sources/ folder. */
#include "plant_token.h"
#ifndef PLANT_TOKEN
#error "plant_token.h must define PLANT_TOKEN (the instantiation token / GUID)"
#endif

#define ANY_STATE (FW_INSTANTIATED | FW_INITIALIZATION | FW_STEP | FW_TERMINATED | FW_FAILED)

/* Allowed-state mask per function (FMI 2.0.4 section 4.2.4; FMI 3.0 section 4.2). */
static const unsigned FW_ALLOWED[FW_FN_COUNT] = {
    [FW_FN_SETUP_EXPERIMENT] = FW_INSTANTIATED,
    [FW_FN_ENTER_INIT] = FW_INSTANTIATED,
    [FW_FN_EXIT_INIT] = FW_INITIALIZATION,
    [FW_FN_DO_STEP] = FW_STEP,
    [FW_FN_TERMINATE] = FW_STEP,
    [FW_FN_RESET] = ANY_STATE,
    [FW_FN_GET] = FW_INITIALIZATION | FW_STEP | FW_TERMINATED | FW_FAILED,
    [FW_FN_SET_INPUT] = FW_INSTANTIATED | FW_INITIALIZATION | FW_STEP,
    [FW_FN_SET_PARAMETER] = FW_INSTANTIATED | FW_INITIALIZATION,
};

static const char *state_name(FwState state) {
    switch (state) {
    case FW_INSTANTIATED: return "Instantiated";
    case FW_INITIALIZATION: return "InitializationMode";
    case FW_STEP: return "StepMode";
    case FW_TERMINATED: return "Terminated";
    case FW_FAILED: return "Failed";
    }
    return "?";
}

void fw_log(FwInstance *inst, FwStatus status, const char *category, const char *fmt, ...) {
    if (inst->log_fn == NULL || inst->logger == NULL || (status == FW_OK && !inst->logging_on)) {
        return;
    }
    char message[512];
    va_list args;
    va_start(args, fmt);
    vsnprintf(message, sizeof message, fmt, args);
    va_end(args);
    inst->log_fn(inst, status, category, message);
}

bool fw_allowed(FwInstance *inst, FwFunction fn, const char *api_name) {
    if (inst == NULL) {
        return false;
    }
    if (FW_ALLOWED[fn] & inst->state) {
        return true;
    }
    fw_log(inst, FW_ERROR, "logStatusError", "%s must not be called in state %s",
           api_name, state_name(inst->state));
    return false;
}

FwStatus fw_unsupported(FwInstance *inst, const char *api_name) {
    if (inst != NULL) {
        fw_log(inst, FW_ERROR, "logStatusError", "%s is not supported by this FMU", api_name);
    }
    return FW_ERROR;
}

static void reset_model(FwInstance *inst) {
    memset(&inst->model, 0, sizeof inst->model);
    plant_vars_set_defaults(&inst->model.var);
    memset(inst->clamped, 0, sizeof inst->clamped);
    inst->start_time_s = 0.0;
    inst->steps = 0;
    inst->frac_s = 0.0;
    inst->state = FW_INSTANTIATED;
}

FwInstance *fw_instantiate(const FwInstantiation *how) {
    FwInstance probe = {.name = (char *)(how->name ? how->name : "?"), .env = how->env,
                        .logger = how->logger, .log_fn = how->log_fn};
    if (how->token == NULL || strcmp(how->token, PLANT_TOKEN) != 0) {
        fw_log(&probe, FW_ERROR, "logStatusError", "instantiation token '%s' does not match '%s'",
               how->token ? how->token : "(null)", PLANT_TOKEN);
        return NULL;
    }
    FwInstance *inst = calloc(1, sizeof *inst);
    char *name_copy = strdup(probe.name);
    if (inst == NULL || name_copy == NULL) {
        free(inst);
        free(name_copy);
        fw_log(&probe, FW_FATAL, "logStatusFatal", "out of memory");
        return NULL;
    }
    inst->name = name_copy;
    inst->env = how->env;
    inst->logger = how->logger;
    inst->log_fn = how->log_fn;
    inst->logging_on = how->logging_on;
    reset_model(inst);
    return inst;
}

void fw_free(FwInstance *inst) {
    if (inst != NULL) {
        free(inst->name);
        free(inst);
    }
}

FwStatus fw_setup_experiment(FwInstance *inst, double start_time_s) {
    if (!fw_allowed(inst, FW_FN_SETUP_EXPERIMENT, "SetupExperiment")) {
        return FW_ERROR;
    }
    if (!isfinite(start_time_s)) {
        fw_log(inst, FW_ERROR, "logStatusError", "start time must be finite, got %g", start_time_s);
        return FW_ERROR;
    }
    inst->start_time_s = start_time_s;
    inst->model.var.time = start_time_s;
    return FW_OK;
}

FwStatus fw_enter_initialization(FwInstance *inst) {
    if (!fw_allowed(inst, FW_FN_ENTER_INIT, "EnterInitializationMode")) {
        return FW_ERROR;
    }
    inst->state = FW_INITIALIZATION;
    return FW_OK;
}

/* Range-check every parameter against the table, then their relations. */
static FwStatus validate_parameters(FwInstance *inst) {
    for (size_t i = 0; i < PLANT_VAR_COUNT; ++i) {
        const PlantVarInfo *info = &PLANT_VARS[i];
        if (info->kind != PLANT_KIND_PARAMETER || info->type != PLANT_TYPE_REAL) {
            continue;
        }
        double value = *plant_var_real(&inst->model.var, info);
        if (!(value >= info->lo && value <= info->hi)) {
            fw_log(inst, FW_ERROR, "logStatusError",
                   "parameter '%s' = %g is invalid: expected a number in [%g, %g] %s",
                   info->name, value, info->lo, info->hi, info->unit);
            return FW_ERROR;
        }
    }
    char buf[256];
    const char *problem = plant_check_parameters(&inst->model, buf, sizeof buf);
    if (problem != NULL) {
        fw_log(inst, FW_ERROR, "logStatusError", "%s", problem);
        return FW_ERROR;
    }
    return FW_OK;
}

FwStatus fw_exit_initialization(FwInstance *inst) {
    if (!fw_allowed(inst, FW_FN_EXIT_INIT, "ExitInitializationMode")) {
        return FW_ERROR;
    }
    if (validate_parameters(inst) != FW_OK) {
        return FW_ERROR; /* stays in initialization mode: fix the parameter and retry */
    }
    plant_initialize(&inst->model);
    inst->steps = 0;
    inst->frac_s = 0.0;
    inst->model.var.time = inst->start_time_s;
    inst->state = FW_STEP;
    return FW_OK;
}

static double time_now(const FwInstance *inst) {
    return inst->start_time_s + (double)inst->steps * PLANT_STEP_S + inst->frac_s;
}

static bool outputs_finite(const PlantVariables *v) {
    return isfinite(v->x) && isfinite(v->v) && isfinite(v->a) && isfinite(v->wheel_speed_fl) &&
           isfinite(v->wheel_speed_rl) && isfinite(v->brake_pressure) && isfinite(v->drive_force) &&
           isfinite(v->y) && isfinite(v->yaw) && isfinite(v->yaw_rate) && isfinite(v->ay) &&
           isfinite(v->vx) && isfinite(v->vy) && isfinite(v->delta) && isfinite(v->ax);
}

/* Where the step ends on the grid: whole steps *end plus *end_frac_s in [0, h). A point
 * within GRID_TOLERANCE steps of a grid point is that grid point, so whole multiples of
 * the internal step take exactly the whole steps they always took. */
#define GRID_TOLERANCE 1e-6
static void grid_position(const FwInstance *inst, double t_end_s, long long *end,
                          double *end_frac_s) {
    double rel_s = t_end_s - inst->start_time_s;
    double cells = rel_s / PLANT_STEP_S;
    *end = llround(cells);
    *end_frac_s = 0.0;
    if (fabs(cells - (double)*end) > GRID_TOLERANCE) {
        *end = (long long)floor(cells);
        *end_frac_s = rel_s - (double)*end * PLANT_STEP_S;
    }
}

/* Integrate to (end, end_frac_s): complete the current grid cell, take whole steps, then a
 * shorter last sub-step to a communication point that lies between two grid points. */
static void advance(FwInstance *inst, long long end, double end_frac_s) {
    while (inst->steps < end || inst->frac_s < end_frac_s) {
        bool enters_cell = inst->frac_s == 0.0;
        double cell_end_s = inst->steps < end ? PLANT_STEP_S : end_frac_s;
        plant_step(&inst->model, cell_end_s - inst->frac_s, enters_cell);
        if (inst->steps < end) {
            ++inst->steps;
            inst->frac_s = 0.0;
        } else {
            inst->frac_s = end_frac_s;
        }
    }
}

FwStatus fw_do_step(FwInstance *inst, double t_s, double h_s, double *last_time_s) {
    if (!fw_allowed(inst, FW_FN_DO_STEP, "DoStep")) {
        return FW_ERROR;
    }
    double now_s = time_now(inst);
    *last_time_s = now_s;
    if (!(h_s > 0.0) || !isfinite(h_s) || !(fabs(t_s - now_s) <= GRID_TOLERANCE * PLANT_STEP_S)) {
        fw_log(inst, FW_ERROR, "logStatusError",
               "DoStep(currentCommunicationPoint=%.17g, step=%.17g): expected the point %.17g "
               "and a positive step", t_s, h_s, now_s);
        return FW_ERROR;
    }
    long long end;
    double end_frac_s;
    grid_position(inst, t_s + h_s, &end, &end_frac_s);
    if (end < inst->steps || (end == inst->steps && !(end_frac_s > inst->frac_s))) {
        fw_log(inst, FW_ERROR, "logStatusError",
               "DoStep step %.17g s is below the %g s time resolution", h_s,
               GRID_TOLERANCE * PLANT_STEP_S);
        return FW_ERROR;
    }
    advance(inst, end, end_frac_s);
    plant_publish_outputs(&inst->model);
    inst->model.var.time = time_now(inst);
    *last_time_s = inst->model.var.time;
    if (!outputs_finite(&inst->model.var)) {
        inst->state = FW_FAILED;
        fw_log(inst, FW_ERROR, "logStatusError", "non-finite output at t = %g s", *last_time_s);
        return FW_ERROR;
    }
    return FW_OK;
}

FwStatus fw_terminate(FwInstance *inst) {
    if (!fw_allowed(inst, FW_FN_TERMINATE, "Terminate")) {
        return FW_ERROR;
    }
    inst->state = FW_TERMINATED;
    return FW_OK;
}

FwStatus fw_reset(FwInstance *inst) {
    if (!fw_allowed(inst, FW_FN_RESET, "Reset")) {
        return FW_ERROR;
    }
    reset_model(inst);
    return FW_OK;
}
