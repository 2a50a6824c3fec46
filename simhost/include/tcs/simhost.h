/* The simulation plug-in ABI: the only way the coordinator talks to a
 * physics engine. A plug-in is a table of C functions; the built-in ODE
 * plug-in is one, and another engine can be wrapped behind the same table
 * in a shared library that exports tcs_simhost_plugin_entry().
 *
 * Stable C ABI: plain types only, no exceptions across it, errors as
 * return codes plus a message in a caller-provided buffer. Bump
 * TCS_SIMHOST_ABI_VERSION on any incompatible change. */
#ifndef TCS_SIMHOST_H
#define TCS_SIMHOST_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_SIMHOST_ABI_VERSION 2u

/* A world instance, opaque to the coordinator. */
typedef struct tcs_sim tcs_sim;

/* One model instance in a world: `name` prefixes its signals
 * ("<name>.<joint>.position"); `type` is the model ("pendulum", ...). */
struct tcs_sim_model {
	const char *name;
	const char *type;
	const char *const *param_keys; /* nparams model parameters */
	const double *param_values;
	size_t nparams;
};

enum tcs_sim_signal_flags {
	TCS_SIM_SIGNAL_WRITABLE = 1u << 0, /* an input (effort): write() accepts it */
};

/* What a signal is: its full name, how many values it carries (1 for a
 * joint position/velocity/effort, 7 for a pose x y z qw qx qy qz, 6 for a
 * twist vx vy vz wx wy wz), its unit, whether it can be written, and the
 * rate a sensor of the model's own samples it at (0: every step; the
 * coordinator holds a sample between updates). Version 2 added rate_hz. */
struct tcs_sim_signal_info {
	const char *name;
	uint32_t width;
	uint32_t flags;
	const char *unit;
	double rate_hz;
};

struct tcs_simhost_plugin {
	uint32_t abi_version; /* TCS_SIMHOST_ABI_VERSION */
	const char *name;     /* the engine, e.g. "ode" */

	/* Model types this plug-in knows, NULL-terminated. */
	const char *const *model_types;

	/* Creates a world of the given models advancing step_ns per step().
	 * On failure returns NULL with a one-line reason in err (an unknown
	 * model type or parameter, a bad value): the caller adds file:line. */
	tcs_sim *(*create)(const struct tcs_sim_model *models, size_t nmodels, int64_t step_ns, char *err,
			   size_t errlen);

	/* Advances the world by one step. 0, or -1 with a reason in err. */
	int (*step)(tcs_sim *sim, char *err, size_t errlen);

	/* The world's signals: count, and the i-th one's description (valid
	 * until destroy). Indices are stable for the life of the world. */
	size_t (*signal_count)(const tcs_sim *sim);
	const struct tcs_sim_signal_info *(*signal_info)(const tcs_sim *sim, size_t index);

	/* Reads signal `index` into out[0..width-1]: its value at the end of
	 * the last step (or at creation). 0, or -1 for a bad index. */
	int (*read)(const tcs_sim *sim, size_t index, double *out);

	/* Sets a writable signal (an effort), held from the next step on until
	 * written again (zero-order hold). 0, or -1 for a bad index or a signal
	 * that is not writable. Saturation is the caller's business. */
	int (*write)(tcs_sim *sim, size_t index, const double *values);

	void (*destroy)(tcs_sim *sim);

	/* The step the models' own files ask for (an SDF world's
	 * <physics><max_step_size>), in ns; 0 if none does. A scenario that
	 * sets no step of its own takes it. Version 2. */
	int64_t (*file_step_ns)(const tcs_sim *sim);
};

/* What a plug-in shared library exports. */
typedef const struct tcs_simhost_plugin *(*tcs_simhost_plugin_entry_fn)(void);
#define TCS_SIMHOST_PLUGIN_ENTRY "tcs_simhost_plugin_entry"

/* The built-in ODE plug-in (linked into the coordinator). */
const struct tcs_simhost_plugin *tcs_simhost_ode_plugin(void);

#ifdef __cplusplus
}
#endif
#endif
