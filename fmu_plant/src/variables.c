/* The variable table expanded from variables.def, and a dense vr lookup. */
#include "variables.h"

const PlantVarInfo PLANT_VARS[] = {
#define PLANT_VAR(vr, name, kind, type, start, lo, hi, unit, desc) \
    {vr, #name, PLANT_KIND_##kind, PLANT_TYPE_##type, offsetof(PlantVariables, name), start, lo, hi, unit},
#include "variables.def"
#undef PLANT_VAR
};

const size_t PLANT_VAR_COUNT = sizeof(PLANT_VARS) / sizeof(PLANT_VARS[0]);

/* Table position of each variable, in table order. */
enum {
#define PLANT_VAR(vr, name, kind, type, start, lo, hi, unit, desc) PLANT_INDEX_##name,
#include "variables.def"
#undef PLANT_VAR
    PLANT_INDEX_COUNT
};

/* vr -> table position + 1; 0 marks an unused value reference. */
static const unsigned char VR_INDEX[PLANT_VR_CAP] = {
#define PLANT_VAR(vr, name, kind, type, start, lo, hi, unit, desc) [vr] = PLANT_INDEX_##name + 1,
#include "variables.def"
#undef PLANT_VAR
};

const PlantVarInfo *plant_var_lookup(unsigned vr) {
    if (vr >= PLANT_VR_CAP || VR_INDEX[vr] == 0) {
        return NULL;
    }
    return &PLANT_VARS[VR_INDEX[vr] - 1];
}

void plant_vars_set_defaults(PlantVariables *vars) {
    for (size_t i = 0; i < PLANT_VAR_COUNT; ++i) {
        const PlantVarInfo *info = &PLANT_VARS[i];
        if (info->type == PLANT_TYPE_REAL) {
            *plant_var_real(vars, info) = info->start;
        } else {
            *plant_var_bool(vars, info) = info->start != 0.0;
        }
    }
}
