/* Get and set by value reference: type and causality checks, NaN refusal and
 * clamping of inputs to their table range. */
#include "framework.h"

#include <math.h>

static const PlantVarInfo *lookup(FwInstance *inst, unsigned vr, PlantType type) {
    const PlantVarInfo *info = plant_var_lookup(vr);
    if (info == NULL) {
        fw_log(inst, FW_ERROR, "logStatusError", "unknown value reference %u", vr);
        return NULL;
    }
    if (info->type != type) {
        fw_log(inst, FW_ERROR, "logStatusError", "variable '%s' (vr %u) is %s, accessed as %s",
               info->name, vr, info->type == PLANT_TYPE_REAL ? "Real" : "Boolean",
               type == PLANT_TYPE_REAL ? "Real" : "Boolean");
        return NULL;
    }
    return info;
}

/* May this variable be set now? Inputs in any live state, parameters before init. */
static bool settable(FwInstance *inst, const PlantVarInfo *info) {
    switch (info->kind) {
    case PLANT_KIND_INPUT:
        return fw_allowed(inst, FW_FN_SET_INPUT, "Set (input)");
    case PLANT_KIND_PARAMETER:
        return fw_allowed(inst, FW_FN_SET_PARAMETER, "Set (fixed parameter)");
    default:
        fw_log(inst, FW_ERROR, "logStatusError", "variable '%s' is not an input or parameter; "
               "it cannot be set", info->name);
        return false;
    }
}

FwStatus fw_get_real(FwInstance *inst, unsigned vr, double *value) {
    if (!fw_allowed(inst, FW_FN_GET, "Get")) {
        return FW_ERROR;
    }
    const PlantVarInfo *info = lookup(inst, vr, PLANT_TYPE_REAL);
    if (info == NULL) {
        return FW_ERROR;
    }
    *value = *plant_var_real(&inst->model.var, info);
    return FW_OK;
}

static FwStatus clamp_input(FwInstance *inst, const PlantVarInfo *info, double *value) {
    double wanted = *value;
    *value = wanted < info->lo ? info->lo : (wanted > info->hi ? info->hi : wanted);
    bool clamped = *value != wanted;
    bool was_clamped = inst->clamped[info->vr];
    inst->clamped[info->vr] = clamped;
    if (clamped && !was_clamped) {
        fw_log(inst, FW_WARNING, "logStatusWarning",
               "input '%s' = %g is outside [%g, %g] %s: clamped to %g",
               info->name, wanted, info->lo, info->hi, info->unit, *value);
        return FW_WARNING;
    }
    return FW_OK;
}

FwStatus fw_set_real(FwInstance *inst, unsigned vr, double value) {
    if (inst == NULL) {
        return FW_ERROR;
    }
    const PlantVarInfo *info = lookup(inst, vr, PLANT_TYPE_REAL);
    if (info == NULL || !settable(inst, info)) {
        return FW_ERROR;
    }
    FwStatus status = FW_OK;
    if (info->kind == PLANT_KIND_INPUT) {
        if (!isfinite(value)) {
            fw_log(inst, FW_ERROR, "logStatusError",
                   "input '%s' = %g refused: expected a finite number; keeping %g",
                   info->name, value, *plant_var_real(&inst->model.var, info));
            return FW_ERROR;
        }
        status = clamp_input(inst, info, &value);
    }
    /* Parameters are range-checked as a set at ExitInitializationMode. */
    *plant_var_real(&inst->model.var, info) = value;
    return status;
}

FwStatus fw_get_bool(FwInstance *inst, unsigned vr, bool *value) {
    if (!fw_allowed(inst, FW_FN_GET, "Get")) {
        return FW_ERROR;
    }
    const PlantVarInfo *info = lookup(inst, vr, PLANT_TYPE_BOOL);
    if (info == NULL) {
        return FW_ERROR;
    }
    *value = *plant_var_bool(&inst->model.var, info);
    return FW_OK;
}

FwStatus fw_set_bool(FwInstance *inst, unsigned vr, bool value) {
    if (inst == NULL) {
        return FW_ERROR;
    }
    const PlantVarInfo *info = lookup(inst, vr, PLANT_TYPE_BOOL);
    if (info == NULL || !settable(inst, info)) {
        return FW_ERROR;
    }
    *plant_var_bool(&inst->model.var, info) = value;
    return FW_OK;
}
