/* The FMI 2.0 functions of a dyadc FMU (Model Exchange and Co-Simulation): each translates its
   arguments for the one core (fmu_core.h) and back. fmi2Status numbers its first five statuses
   as the core's DY_ statuses. */
#include <string.h>

#include "fmi2_api.h"
#include "fmu_core.h"

#define C(component) ((DyInstance *)(component))

static void write_log(const void *environment, void (*function)(void), const char *instance, int status,
                      const char *category, const char *message) {
    const fmi2CallbackFunctions *callbacks = (const fmi2CallbackFunctions *)environment;
    (void)function;
    if (callbacks && callbacks->logger)
        callbacks->logger(callbacks->componentEnvironment, instance, (fmi2Status)status, category, "%s", message);
}

DYFMI_EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
DYFMI_EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

DYFMI_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String location,
                                           const fmi2CallbackFunctions *callbacks, fmi2Boolean visible,
                                           fmi2Boolean logging) {
    DyLogger logger = {write_log, callbacks, NULL};
    (void)location; (void)visible;
    return dy_instantiate(name, guid, type == fmi2CoSimulation, logging, logger);
}

DYFMI_EXPORT void fmi2FreeInstance(fmi2Component c) { dy_free_instance(C(c)); }

DYFMI_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cats[]) {
    (void)n; (void)cats;
    C(c)->logging = on;
    return fmi2OK;
}

DYFMI_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                                            fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
    (void)stop_defined; (void)stop;
    return (fmi2Status)dy_setup_experiment(C(c), tolerance_defined ? tolerance : 0.0, start);
}

DYFMI_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return (fmi2Status)dy_set_mode(C(c), DY_INITIALIZATION); }
DYFMI_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { return (fmi2Status)dy_exit_initialization(C(c)); }
DYFMI_EXPORT fmi2Status fmi2Terminate(fmi2Component c) { return (fmi2Status)dy_set_mode(C(c), DY_TERMINATED); }
DYFMI_EXPORT fmi2Status fmi2Reset(fmi2Component c) { dy_reset(C(c)); return fmi2OK; }

DYFMI_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[]) {
    return (fmi2Status)dy_get_real(C(c), vr, n, value);
}
DYFMI_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[]) {
    return (fmi2Status)dy_set_real(C(c), vr, n, value);
}

#define NO_VARIABLES(function, element, type)                                                        \
    DYFMI_EXPORT fmi2Status function(fmi2Component c, const fmi2ValueReference vr[], size_t n, element v[]) { \
        (void)vr; (void)v; return (fmi2Status)dy_no_variables(C(c), n, type);                         \
    }
NO_VARIABLES(fmi2GetInteger, fmi2Integer, "Integer")
NO_VARIABLES(fmi2GetBoolean, fmi2Boolean, "Boolean")
NO_VARIABLES(fmi2GetString, fmi2String, "String")
NO_VARIABLES(fmi2SetInteger, const fmi2Integer, "Integer")
NO_VARIABLES(fmi2SetBoolean, const fmi2Boolean, "Boolean")
NO_VARIABLES(fmi2SetString, const fmi2String, "String")

/* ---- Model Exchange ------------------------------------------------------------------------------ */
DYFMI_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c) { return (fmi2Status)dy_set_mode(C(c), DY_EVENT); }

DYFMI_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    int defined = 0;
    double next = 0.0;
    fmi2Status status = (fmi2Status)dy_update_discrete_states(C(c), &defined, &next);
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = defined;
    info->nextEventTime = next;
    return status;
}

DYFMI_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return (fmi2Status)dy_set_mode(C(c), DY_CONTINUOUS); }

DYFMI_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set_prior, fmi2Boolean *enter_event_mode,
                                                    fmi2Boolean *terminate) {
    (void)no_set_prior;
    *enter_event_mode = fmi2False;
    *terminate = fmi2False;
    return (fmi2Status)dy_completed_integrator_step(C(c));
}

DYFMI_EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) { return (fmi2Status)dy_set_time(C(c), time); }
DYFMI_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    return (fmi2Status)dy_set_states(C(c), x, n);
}
DYFMI_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    return (fmi2Status)dy_get_states(C(c), x, n);
}
DYFMI_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t n) {
    return (fmi2Status)dy_get_derivatives(C(c), derivatives, n);
}
DYFMI_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real indicators[], size_t n) {
    return (fmi2Status)dy_get_event_indicators(C(c), indicators, n);
}
DYFMI_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real nominals[], size_t n) {
    return (fmi2Status)dy_get_nominals(C(c), nominals, n);
}

DYFMI_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unknown[], size_t n_unknown,
                                                     const fmi2ValueReference known[], size_t n_known,
                                                     const fmi2Real seed[], fmi2Real sensitivity[]) {
    return (fmi2Status)dy_directional_derivative(C(c), unknown, n_unknown, known, n_known, seed, sensitivity);
}

/* ---- the FMU state ------------------------------------------------------------------------------ */
DYFMI_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) { return (fmi2Status)dy_get_state(C(c), state); }
DYFMI_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) { return (fmi2Status)dy_set_state(C(c), state); }
DYFMI_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) { (void)c; dy_free_state(state); return fmi2OK; }

DYFMI_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) {
    (void)c; (void)s;
    *size = dy_serialized_size();
    return fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size) {
    return (fmi2Status)dy_serialize(C(c), s, (unsigned char *)bytes, size);
}
DYFMI_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s) {
    return (fmi2Status)dy_deserialize(C(c), (const unsigned char *)bytes, size, s);
}

/* ---- Co-Simulation ------------------------------------------------------------------------------ */
DYFMI_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real current, fmi2Real size, fmi2Boolean no_prior) {
    (void)no_prior;
    return (fmi2Status)dy_do_step(C(c), current, size);
}

DYFMI_EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }
DYFMI_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                                    const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)order; (void)value;
    return n ? (fmi2Status)dy_fail(C(c), "input derivatives are not supported (canInterpolateInputs is false)") : fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                                     const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)order; (void)value;
    return n ? (fmi2Status)dy_fail(C(c), "output derivatives are not supported (maxOutputDerivativeOrder is 0)") : fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)c; (void)s; *value = fmi2OK; return fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    if (s != fmi2LastSuccessfulTime) return fmi2Discard;
    *value = C(c)->t;
    return fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)c; (void)s; (void)value; return fmi2Discard;
}
DYFMI_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)c;
    if (s != fmi2Terminated) return fmi2Discard;
    *value = fmi2False;
    return fmi2OK;
}
DYFMI_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)c; (void)s; (void)value; return fmi2Discard;
}
