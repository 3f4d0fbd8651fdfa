/* The core of a dyadc FMU (fmu_model.c and what it includes), which the FMI 2.0 and FMI 3.0
   wrappers (fmi2_functions.c, fmi3_functions.c) both call: each FMI function is a thin
   translation of one of these. Every function returning int returns a DY_ status (fmu_instance.h);
   on an error it has logged what went wrong. Value references are the model's (layout.py): the
   states, their derivatives, the output rows, the parameters, the event indicators, then time. */
#ifndef DYADC_FMU_CORE_H
#define DYADC_FMU_CORE_H

#include "fmu_instance.h"

/* A new instance, or NULL (logged) when `token` is not this FMU's GUID or memory ran out. */
DyInstance *dy_instantiate(const char *name, const char *token, int cosimulation, int logging, DyLogger logger);
void dy_free_instance(DyInstance *c);
void dy_reset(DyInstance *c);
int dy_fail(DyInstance *c, const char *message);
int dy_set_mode(DyInstance *c, int mode);

/* The experiment: the start time, and the Co-Simulation tolerance when `tolerance` > 0. */
int dy_setup_experiment(DyInstance *c, double tolerance, double start);
int dy_exit_initialization(DyInstance *c);

int dy_get_real(DyInstance *c, const unsigned int vr[], size_t n, double value[]);
int dy_set_real(DyInstance *c, const unsigned int vr[], size_t n, const double value[]);
/* Getting or setting n > 0 values of a type this FMU has none of (`type`: its FMI name). */
int dy_no_variables(DyInstance *c, size_t n, const char *type);

/* Event mode: time events and relations settled; the next time event, when there is one. */
int dy_update_discrete_states(DyInstance *c, int *next_event_defined, double *next_event);
/* After an integrator step the importer accepted: the declared bounds checked (DY_ERROR, logged,
   when the model left its domain). Initialization, event updates and Co-Simulation steps check
   them too. */
int dy_completed_integrator_step(DyInstance *c);
int dy_set_time(DyInstance *c, double time);
int dy_set_states(DyInstance *c, const double x[], size_t n);
int dy_get_states(DyInstance *c, double x[], size_t n);
int dy_get_derivatives(DyInstance *c, double derivatives[], size_t n);
int dy_get_event_indicators(DyInstance *c, double indicators[], size_t n);
int dy_get_nominals(DyInstance *c, double nominals[], size_t n);
size_t dy_state_count(void);
size_t dy_event_indicator_count(void);

/* Seeds on states and inputs, sensitivities of derivatives and outputs (exact, eliminated). */
int dy_directional_derivative(DyInstance *c, const unsigned int unknown[], size_t n_unknown,
                              const unsigned int known[], size_t n_known, const double seed[], double sensitivity[]);
/* Seeds on derivatives and outputs, sensitivities of states and inputs (FMI 3.0's adjoint). */
int dy_adjoint_derivative(DyInstance *c, const unsigned int unknown[], size_t n_unknown,
                          const unsigned int known[], size_t n_known, const double seed[], double sensitivity[]);

/* The FMU state: a copy of the instance (get reuses *state when it holds one), and as bytes. */
int dy_get_state(DyInstance *c, void **state);
int dy_set_state(DyInstance *c, const void *state);
void dy_free_state(void **state);
size_t dy_serialized_size(void);
int dy_serialize(DyInstance *c, const void *state, unsigned char bytes[], size_t size);
int dy_deserialize(DyInstance *c, const unsigned char bytes[], size_t size, void **state);

/* Co-Simulation: integrate from `current` (the FMU's time) to current + size. */
int dy_do_step(DyInstance *c, double current, double size);

#endif
