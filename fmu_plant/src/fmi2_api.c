/* FMI 2.0 co-simulation API over the shared framework (framework.h).
 * Every exported function checks its instance and call order first. */
#include <string.h>

#include "fmi2Functions.h"
#include "framework.h"

#define INST(c) ((FwInstance *)(c))

static void fmi2_log(const FwInstance *inst, FwStatus status, const char *category,
                     const char *message) {
    fmi2CallbackLogger logger = (fmi2CallbackLogger)inst->logger;
    logger((fmi2ComponentEnvironment)inst->env, inst->name, (fmi2Status)status, category, "%s",
           message);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    if (c == NULL) {
        return fmi2Error;
    }
    INST(c)->logging_on = loggingOn != fmi2False;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    (void)fmuResourceLocation;
    (void)visible;
    FwInstantiation how = {
        .name = instanceName,
        .token = fmuGUID,
        .log_fn = fmi2_log,
        .logger = functions ? (FwCallback)functions->logger : NULL,
        .env = functions ? functions->componentEnvironment : NULL,
        .logging_on = loggingOn != fmi2False,
    };
    if (fmuType != fmi2CoSimulation) {
        if (how.logger != NULL) {
            ((fmi2CallbackLogger)how.logger)(how.env, instanceName, fmi2Error, "logStatusError",
                                             "%s", "only fmi2CoSimulation is supported");
        }
        return NULL;
    }
    return fw_instantiate(&how);
}

void fmi2FreeInstance(fmi2Component c) { fw_free(INST(c)); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    return (fmi2Status)fw_setup_experiment(INST(c), startTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    return (fmi2Status)fw_enter_initialization(INST(c));
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    return (fmi2Status)fw_exit_initialization(INST(c));
}

fmi2Status fmi2Terminate(fmi2Component c) { return (fmi2Status)fw_terminate(INST(c)); }
fmi2Status fmi2Reset(fmi2Component c) { return (fmi2Status)fw_reset(INST(c)); }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    FwStatus status = c ? FW_OK : FW_ERROR;
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_get_real(INST(c), vr[i], &value[i]));
    }
    return (fmi2Status)status;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    FwStatus status = c ? FW_OK : FW_ERROR;
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_set_real(INST(c), vr[i], value[i]));
    }
    return (fmi2Status)status;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    FwStatus status = c ? FW_OK : FW_ERROR;
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        bool b = false;
        status = fw_worst(status, fw_get_bool(INST(c), vr[i], &b));
        value[i] = b ? fmi2True : fmi2False;
    }
    return (fmi2Status)status;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    FwStatus status = c ? FW_OK : FW_ERROR;
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_set_bool(INST(c), vr[i], value[i] != fmi2False));
    }
    return (fmi2Status)status;
}

/* The plant has no Integer or String variables: any reference is unknown. */
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return nvr == 0 && c ? fmi2OK : (fmi2Status)fw_unsupported(INST(c), "fmi2GetInteger");
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return nvr == 0 && c ? fmi2OK : (fmi2Status)fw_unsupported(INST(c), "fmi2SetInteger");
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    (void)vr;
    (void)value;
    return nvr == 0 && c ? fmi2OK : (fmi2Status)fw_unsupported(INST(c), "fmi2GetString");
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    (void)vr;
    (void)value;
    return nvr == 0 && c ? fmi2OK : (fmi2Status)fw_unsupported(INST(c), "fmi2SetString");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    double last_time_s;
    return (fmi2Status)fw_do_step(INST(c), currentCommunicationPoint, communicationStepSize,
                                  &last_time_s);
}

fmi2Status fmi2CancelStep(fmi2Component c) { return (fmi2Status)fw_unsupported(INST(c), "fmi2CancelStep"); }

/* Declared unsupported in modelDescription.xml (canGetAndSetFMUstate="false" etc.). */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetFMUstate");
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
    (void)s;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2SetFMUstate");
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2FreeFMUstate");
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) {
    (void)s;
    (void)size;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
    (void)s;
    (void)b;
    (void)n;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s) {
    (void)b;
    (void)n;
    (void)s;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real dv[], fmi2Real dz[]) {
    (void)u; (void)nu; (void)z; (void)nz; (void)dv; (void)dz;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetRealOutputDerivatives");
}

/* No asynchronous steps: status queries are not available (FMI 2.0.4 section 4.2.3). */
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    (void)s; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)s; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetBooleanStatus");
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s; (void)value;
    return (fmi2Status)fw_unsupported(INST(c), "fmi2GetStringStatus");
}
