/* FMI 3.0 co-simulation API over the shared framework (framework.h).
 * Only Float64 and Boolean variables exist; other types, events, clocks,
 * FMU states and model exchange are declared unsupported and return an error. */
#include "fmi3Functions.h"
#include "framework.h"

#define INST(i) ((FwInstance *)(i))

static void fmi3_log(const FwInstance *inst, FwStatus status, const char *category,
                     const char *message) {
    fmi3LogMessageCallback logger = (fmi3LogMessageCallback)inst->logger;
    logger((fmi3InstanceEnvironment)inst->env, (fmi3Status)status, category, message);
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    (void)nCategories;
    (void)categories;
    if (instance == NULL) {
        return fmi3Error;
    }
    INST(instance)->logging_on = loggingOn;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    (void)resourcePath;
    (void)visible;
    (void)eventModeUsed; /* the plant has no events: step mode only */
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    FwInstantiation how = {
        .name = instanceName,
        .token = instantiationToken,
        .log_fn = fmi3_log,
        .logger = (FwCallback)logMessage,
        .env = instanceEnvironment,
        .logging_on = loggingOn,
    };
    return fw_instantiate(&how);
}

static fmi3Instance refuse_interface(fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
                                     const char *what) {
    if (log != NULL) {
        log(env, fmi3Error, "logStatusError", what);
    }
    return NULL;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    return refuse_interface(instanceEnvironment, logMessage, "model exchange is not supported");
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    return refuse_interface(instanceEnvironment, logMessage, "scheduled execution is not supported");
}

void fmi3FreeInstance(fmi3Instance instance) { fw_free(INST(instance)); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (!fw_allowed(INST(instance), FW_FN_ENTER_INIT, "fmi3EnterInitializationMode")) {
        return fmi3Error;
    }
    FwStatus status = fw_setup_experiment(INST(instance), startTime);
    if (status != FW_OK) {
        return (fmi3Status)status;
    }
    return (fmi3Status)fw_enter_initialization(INST(instance));
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    return (fmi3Status)fw_exit_initialization(INST(instance));
}

fmi3Status fmi3Terminate(fmi3Instance instance) { return (fmi3Status)fw_terminate(INST(instance)); }
fmi3Status fmi3Reset(fmi3Instance instance) { return (fmi3Status)fw_reset(INST(instance)); }

static FwStatus count_matches(FwInstance *inst, size_t nvr, size_t nValues) {
    if (inst == NULL) {
        return FW_ERROR;
    }
    if (nvr != nValues) {
        fw_log(inst, FW_ERROR, "logStatusError",
               "%zu values for %zu value references; all variables are scalars", nValues, nvr);
        return FW_ERROR;
    }
    return FW_OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Float64 values[], size_t nValues) {
    FwStatus status = count_matches(INST(instance), nvr, nValues);
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_get_real(INST(instance), vr[i], &values[i]));
    }
    return (fmi3Status)status;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
    FwStatus status = count_matches(INST(instance), nvr, nValues);
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_set_real(INST(instance), vr[i], values[i]));
    }
    return (fmi3Status)status;
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Boolean values[], size_t nValues) {
    FwStatus status = count_matches(INST(instance), nvr, nValues);
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_get_bool(INST(instance), vr[i], &values[i]));
    }
    return (fmi3Status)status;
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Boolean values[], size_t nValues) {
    FwStatus status = count_matches(INST(instance), nvr, nValues);
    for (size_t i = 0; i < nvr && status < FW_ERROR; ++i) {
        status = fw_worst(status, fw_set_bool(INST(instance), vr[i], values[i]));
    }
    return (fmi3Status)status;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    (void)noSetFMUStatePriorToCurrentPoint;
    double last_time_s = 0.0;
    FwStatus status = fw_do_step(INST(instance), currentCommunicationPoint, communicationStepSize,
                                 &last_time_s);
    if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
    if (terminateSimulation) *terminateSimulation = fmi3False;
    if (earlyReturn) *earlyReturn = fmi3False;
    if (lastSuccessfulTime) *lastSuccessfulTime = last_time_s;
    return (fmi3Status)status;
}

#include "fmi3_unsupported.inc"
