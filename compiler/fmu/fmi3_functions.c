/* The FMI 3.0 functions of a dyadc FMU (Model Exchange and Co-Simulation): each translates its
   arguments for the one core (fmu_core.h), the same core the FMI 2.0 functions call
   (fmi2_functions.c). fmi3Status numbers its statuses as the core's DY_ statuses. The model has
   Float64 variables only; clocks, Scheduled Execution, event mode in Co-Simulation and early
   return are not provided (modelDescription.xml says so), and their functions report an error. */
#include <string.h>

#include "fmi3_api.h"
#include "fmu_core.h"

#define C(instance) ((DyInstance *)(instance))
#define S(status) ((fmi3Status)(status))

static void write_log(const void *environment, void (*function)(void), const char *instance, int status,
                      const char *category, const char *message) {
    fmi3LogMessageCallback log_message = (fmi3LogMessageCallback)function;
    (void)instance;
    if (log_message) log_message((fmi3InstanceEnvironment)environment, S(status), category, message);
}

static fmi3Instance instantiate(fmi3String name, fmi3String token, int cosimulation, fmi3Boolean logging,
                                fmi3InstanceEnvironment environment, fmi3LogMessageCallback log_message) {
    DyLogger logger = {write_log, environment, (void (*)(void))log_message};
    return dy_instantiate(name, token, cosimulation, logging, logger);
}

DYFMI_EXPORT const char *fmi3GetVersion(void) { return "3.0"; }

DYFMI_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n, const fmi3String categories[]) {
    (void)n; (void)categories;
    C(c)->logging = on;
    return fmi3OK;
}

DYFMI_EXPORT fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
                                                       fmi3Boolean visible, fmi3Boolean logging,
                                                       fmi3InstanceEnvironment environment,
                                                       fmi3LogMessageCallback log_message) {
    (void)resources; (void)visible;
    return instantiate(name, token, 0, logging, environment, log_message);
}

DYFMI_EXPORT fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
                                                      fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean event_mode,
                                                      fmi3Boolean early_return, const fmi3ValueReference required[],
                                                      size_t n_required, fmi3InstanceEnvironment environment,
                                                      fmi3LogMessageCallback log_message,
                                                      fmi3IntermediateUpdateCallback intermediate_update) {
    DyInstance *c = instantiate(name, token, 1, logging, environment, log_message);
    (void)resources; (void)visible; (void)early_return; (void)required; (void)n_required; (void)intermediate_update;
    if (c && event_mode) {
        dy_fail(c, "event mode in Co-Simulation is not provided (hasEventMode is false): events are handled inside fmi3DoStep");
        dy_free_instance(c);
        return NULL;
    }
    return c;
}

DYFMI_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(fmi3String name, fmi3String token, fmi3String resources,
                                                            fmi3Boolean visible, fmi3Boolean logging,
                                                            fmi3InstanceEnvironment environment,
                                                            fmi3LogMessageCallback log_message,
                                                            fmi3ClockUpdateCallback clock_update,
                                                            fmi3LockPreemptionCallback lock,
                                                            fmi3UnlockPreemptionCallback unlock) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging; (void)clock_update; (void)lock; (void)unlock;
    if (log_message) log_message(environment, fmi3Error, "logStatusError", "this FMU provides no Scheduled Execution");
    return NULL;
}

DYFMI_EXPORT void fmi3FreeInstance(fmi3Instance c) { dy_free_instance(C(c)); }

DYFMI_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tolerance_defined, fmi3Float64 tolerance,
                                                    fmi3Float64 start, fmi3Boolean stop_defined, fmi3Float64 stop) {
    (void)stop_defined; (void)stop;
    dy_set_mode(C(c), DY_INITIALIZATION);
    return S(dy_setup_experiment(C(c), tolerance_defined ? tolerance : 0.0, start));
}

DYFMI_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { return S(dy_exit_initialization(C(c))); }
DYFMI_EXPORT fmi3Status fmi3EnterEventMode(fmi3Instance c) { return S(dy_set_mode(C(c), DY_EVENT)); }
DYFMI_EXPORT fmi3Status fmi3Terminate(fmi3Instance c) { return S(dy_set_mode(C(c), DY_TERMINATED)); }
DYFMI_EXPORT fmi3Status fmi3Reset(fmi3Instance c) { dy_reset(C(c)); return fmi3OK; }

/* ---- values ------------------------------------------------------------------------------------ */
DYFMI_EXPORT fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3Float64 values[],
                                       size_t n_values) {
    if (n_values != n) return S(dy_fail(C(c), "fmi3GetFloat64: every variable is a scalar (nValues must equal nValueReferences)"));
    return S(dy_get_real(C(c), vr, n, values));
}

DYFMI_EXPORT fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Float64 values[],
                                       size_t n_values) {
    if (n_values != n) return S(dy_fail(C(c), "fmi3SetFloat64: every variable is a scalar (nValues must equal nValueReferences)"));
    return S(dy_set_real(C(c), vr, n, values));
}

#define NO_VARIABLES(function, element, type)                                                                     \
    DYFMI_EXPORT fmi3Status function(fmi3Instance c, const fmi3ValueReference vr[], size_t n, element values[], \
                                     size_t n_values) {                                                          \
        (void)vr; (void)values; (void)n_values; return S(dy_no_variables(C(c), n, type));                     \
    }
NO_VARIABLES(fmi3GetFloat32, fmi3Float32, "Float32")
NO_VARIABLES(fmi3GetInt8, fmi3Int8, "Int8")
NO_VARIABLES(fmi3GetUInt8, fmi3UInt8, "UInt8")
NO_VARIABLES(fmi3GetInt16, fmi3Int16, "Int16")
NO_VARIABLES(fmi3GetUInt16, fmi3UInt16, "UInt16")
NO_VARIABLES(fmi3GetInt32, fmi3Int32, "Int32")
NO_VARIABLES(fmi3GetUInt32, fmi3UInt32, "UInt32")
NO_VARIABLES(fmi3GetInt64, fmi3Int64, "Int64")
NO_VARIABLES(fmi3GetUInt64, fmi3UInt64, "UInt64")
NO_VARIABLES(fmi3GetBoolean, fmi3Boolean, "Boolean")
NO_VARIABLES(fmi3GetString, fmi3String, "String")
NO_VARIABLES(fmi3SetFloat32, const fmi3Float32, "Float32")
NO_VARIABLES(fmi3SetInt8, const fmi3Int8, "Int8")
NO_VARIABLES(fmi3SetUInt8, const fmi3UInt8, "UInt8")
NO_VARIABLES(fmi3SetInt16, const fmi3Int16, "Int16")
NO_VARIABLES(fmi3SetUInt16, const fmi3UInt16, "UInt16")
NO_VARIABLES(fmi3SetInt32, const fmi3Int32, "Int32")
NO_VARIABLES(fmi3SetUInt32, const fmi3UInt32, "UInt32")
NO_VARIABLES(fmi3SetInt64, const fmi3Int64, "Int64")
NO_VARIABLES(fmi3SetUInt64, const fmi3UInt64, "UInt64")
NO_VARIABLES(fmi3SetBoolean, const fmi3Boolean, "Boolean")
NO_VARIABLES(fmi3SetString, const fmi3String, "String")

DYFMI_EXPORT fmi3Status fmi3GetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t n, size_t sizes[],
                                      fmi3Binary values[], size_t n_values) {
    (void)vr; (void)sizes; (void)values; (void)n_values; return S(dy_no_variables(C(c), n, "Binary"));
}
DYFMI_EXPORT fmi3Status fmi3SetBinary(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const size_t sizes[],
                                      const fmi3Binary values[], size_t n_values) {
    (void)vr; (void)sizes; (void)values; (void)n_values; return S(dy_no_variables(C(c), n, "Binary"));
}
DYFMI_EXPORT fmi3Status fmi3GetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3Clock values[]) {
    (void)vr; (void)values; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3SetClock(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Clock values[]) {
    (void)vr; (void)values; return S(dy_no_variables(C(c), n, "Clock"));
}

/* ---- dependencies, FMU state, derivatives ------------------------------------------------------ */
DYFMI_EXPORT fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance c, fmi3ValueReference vr, size_t *n) {
    (void)vr; (void)n;
    return S(dy_fail(C(c), "the variables' dependencies are given in modelDescription.xml, not at run time"));
}
DYFMI_EXPORT fmi3Status fmi3GetVariableDependencies(fmi3Instance c, fmi3ValueReference dependent, size_t element[],
                                                    fmi3ValueReference independents[], size_t independent_elements[],
                                                    fmi3DependencyKind kinds[], size_t n) {
    (void)dependent; (void)element; (void)independents; (void)independent_elements; (void)kinds; (void)n;
    return S(dy_fail(C(c), "the variables' dependencies are given in modelDescription.xml, not at run time"));
}

DYFMI_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState *state) { return S(dy_get_state(C(c), state)); }
DYFMI_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState state) { return S(dy_set_state(C(c), state)); }
DYFMI_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState *state) { (void)c; dy_free_state(state); return fmi3OK; }
DYFMI_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState state, size_t *size) {
    (void)c; (void)state;
    *size = dy_serialized_size();
    return fmi3OK;
}
DYFMI_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState state, fmi3Byte bytes[], size_t size) {
    return S(dy_serialize(C(c), state, bytes, size));
}
DYFMI_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte bytes[], size_t size, fmi3FMUState *state) {
    return S(dy_deserialize(C(c), bytes, size, state));
}

DYFMI_EXPORT fmi3Status fmi3GetDirectionalDerivative(fmi3Instance c, const fmi3ValueReference unknowns[], size_t n_unknowns,
                                                     const fmi3ValueReference knowns[], size_t n_knowns,
                                                     const fmi3Float64 seed[], size_t n_seed,
                                                     fmi3Float64 sensitivity[], size_t n_sensitivity) {
    if (n_seed != n_knowns || n_sensitivity != n_unknowns)
        return S(dy_fail(C(c), "fmi3GetDirectionalDerivative: every variable is a scalar (one seed per known, one "
                               "sensitivity per unknown)"));
    return S(dy_directional_derivative(C(c), unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity));
}
DYFMI_EXPORT fmi3Status fmi3GetAdjointDerivative(fmi3Instance c, const fmi3ValueReference unknowns[], size_t n_unknowns,
                                                 const fmi3ValueReference knowns[], size_t n_knowns,
                                                 const fmi3Float64 seed[], size_t n_seed,
                                                 fmi3Float64 sensitivity[], size_t n_sensitivity) {
    if (n_seed != n_unknowns || n_sensitivity != n_knowns)
        return S(dy_fail(C(c), "fmi3GetAdjointDerivative: every variable is a scalar (one seed per unknown, one "
                               "sensitivity per known)"));
    return S(dy_adjoint_derivative(C(c), unknowns, n_unknowns, knowns, n_knowns, seed, sensitivity));
}

/* ---- clocks and configuration: none ------------------------------------------------------------- */
#define NOT_PROVIDED(what) S(dy_fail(C(c), what " is not provided: this FMU has no clocks and no structural parameters"))
DYFMI_EXPORT fmi3Status fmi3EnterConfigurationMode(fmi3Instance c) { return NOT_PROVIDED("configuration mode"); }
DYFMI_EXPORT fmi3Status fmi3ExitConfigurationMode(fmi3Instance c) { return NOT_PROVIDED("configuration mode"); }
DYFMI_EXPORT fmi3Status fmi3GetIntervalDecimal(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3Float64 v[],
                                               fmi3IntervalQualifier q[]) {
    (void)vr; (void)v; (void)q; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3GetIntervalFraction(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3UInt64 k[],
                                                fmi3UInt64 r[], fmi3IntervalQualifier q[]) {
    (void)vr; (void)k; (void)r; (void)q; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3GetShiftDecimal(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3Float64 v[]) {
    (void)vr; (void)v; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3GetShiftFraction(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3UInt64 k[],
                                             fmi3UInt64 r[]) {
    (void)vr; (void)k; (void)r; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3SetIntervalDecimal(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Float64 v[]) {
    (void)vr; (void)v; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3SetIntervalFraction(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 k[],
                                                const fmi3UInt64 r[]) {
    (void)vr; (void)k; (void)r; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3SetShiftDecimal(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Float64 v[]) {
    (void)vr; (void)v; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3SetShiftFraction(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 k[],
                                             const fmi3UInt64 r[]) {
    (void)vr; (void)k; (void)r; return S(dy_no_variables(C(c), n, "Clock"));
}
DYFMI_EXPORT fmi3Status fmi3ActivateModelPartition(fmi3Instance c, fmi3ValueReference clock, fmi3Float64 time) {
    (void)clock; (void)time; return S(dy_fail(C(c), "this FMU provides no Scheduled Execution"));
}

/* ---- event and continuous-time modes (Model Exchange) -------------------------------------------- */
DYFMI_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance c) { (void)c; return fmi3OK; }

DYFMI_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean *update_needed, fmi3Boolean *terminate,
                                                 fmi3Boolean *nominals_changed, fmi3Boolean *values_changed,
                                                 fmi3Boolean *next_defined, fmi3Float64 *next_time) {
    int defined = 0;
    double next = 0.0;
    fmi3Status status = S(dy_update_discrete_states(C(c), &defined, &next));
    *update_needed = fmi3False;
    *terminate = fmi3False;
    *nominals_changed = fmi3False;
    *values_changed = fmi3False;
    *next_defined = defined != 0;
    *next_time = next;
    return status;
}

DYFMI_EXPORT fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) { return S(dy_set_mode(C(c), DY_CONTINUOUS)); }

DYFMI_EXPORT fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean no_set_prior, fmi3Boolean *enter_event_mode,
                                                    fmi3Boolean *terminate) {
    (void)no_set_prior;
    *enter_event_mode = fmi3False;
    *terminate = fmi3False;
    return (fmi3Status)dy_completed_integrator_step(C(c));
}

DYFMI_EXPORT fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 time) { return S(dy_set_time(C(c), time)); }
DYFMI_EXPORT fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64 x[], size_t n) { return S(dy_set_states(C(c), x, n)); }
DYFMI_EXPORT fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) { return S(dy_get_states(C(c), x, n)); }
DYFMI_EXPORT fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64 derivatives[], size_t n) {
    return S(dy_get_derivatives(C(c), derivatives, n));
}
DYFMI_EXPORT fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64 indicators[], size_t n) {
    return S(dy_get_event_indicators(C(c), indicators, n));
}
DYFMI_EXPORT fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64 nominals[], size_t n) {
    return S(dy_get_nominals(C(c), nominals, n));
}
DYFMI_EXPORT fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t *n) { (void)c; *n = dy_event_indicator_count(); return fmi3OK; }
DYFMI_EXPORT fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t *n) { (void)c; *n = dy_state_count(); return fmi3OK; }

/* ---- Co-Simulation ------------------------------------------------------------------------------ */
DYFMI_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance c) { return S(dy_set_mode(C(c), DY_STEP)); }

DYFMI_EXPORT fmi3Status fmi3GetOutputDerivatives(fmi3Instance c, const fmi3ValueReference vr[], size_t n, const fmi3Int32 orders[],
                                                 fmi3Float64 values[], size_t n_values) {
    (void)vr; (void)orders; (void)values; (void)n_values;
    return n ? S(dy_fail(C(c), "output derivatives are not provided (maxOutputDerivativeOrder is 0)")) : fmi3OK;
}

DYFMI_EXPORT fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 current, fmi3Float64 size, fmi3Boolean no_set_prior,
                                   fmi3Boolean *event_handling_needed, fmi3Boolean *terminate, fmi3Boolean *early_return,
                                   fmi3Float64 *last_successful_time) {
    fmi3Status status = S(dy_do_step(C(c), current, size));
    (void)no_set_prior;
    *event_handling_needed = fmi3False;
    *terminate = fmi3False;
    *early_return = fmi3False;
    *last_successful_time = C(c)->t;
    return status;
}
