/* The plant's variables as a C struct and a lookup table, both expanded from
 * variables.def so that C and the model descriptions cannot disagree. */
#ifndef PLANT_VARIABLES_H
#define PLANT_VARIABLES_H

#include <stdbool.h>
#include <stddef.h>

/* Only the FMI functions are exported; the plant's own symbols stay inside the library,
 * whoever builds it (our cmake build also sets hidden visibility; fmpy's does not). */
#if defined(__GNUC__)
#pragma GCC visibility push(hidden)
#endif

typedef enum {
    PLANT_KIND_INDEPENDENT,
    PLANT_KIND_INPUT,
    PLANT_KIND_OUTPUT,
    PLANT_KIND_PARAMETER
} PlantKind;

typedef enum { PLANT_TYPE_REAL, PLANT_TYPE_BOOL } PlantType;

#define PLANT_CTYPE_REAL double
#define PLANT_CTYPE_BOOL bool

/* Every variable by name, in table order (e.g. vars.mass, vars.throttle). */
typedef struct {
#define PLANT_VAR(vr, name, kind, type, start, lo, hi, unit, desc) PLANT_CTYPE_##type name;
#include "variables.def"
#undef PLANT_VAR
} PlantVariables;

typedef struct {
    unsigned vr;
    const char *name;
    PlantKind kind;
    PlantType type;
    size_t offset; /* of the field in PlantVariables */
    double start;
    double lo;
    double hi;
    const char *unit;
} PlantVarInfo;

/* Value references must stay below this (a dense vr -> entry index). */
#define PLANT_VR_CAP 128

extern const PlantVarInfo PLANT_VARS[];
extern const size_t PLANT_VAR_COUNT;

/* Entry for a value reference, or NULL if there is none. */
const PlantVarInfo *plant_var_lookup(unsigned vr);

/* Write every start value from the table into vars. */
void plant_vars_set_defaults(PlantVariables *vars);

static inline double *plant_var_real(PlantVariables *vars, const PlantVarInfo *info) {
    return (double *)((char *)vars + info->offset);
}

static inline bool *plant_var_bool(PlantVariables *vars, const PlantVarInfo *info) {
    return (bool *)((char *)vars + info->offset);
}

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif
