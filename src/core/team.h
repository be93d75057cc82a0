/* team.h - the context's worker threads for loops that run many times a second (one per shot
 * of the shooting solver), where an OpenMP parallel region per loop leaves libgomp's idle
 * threads spinning (up to ~3 ms each time) while the caller runs the serial part between loops:
 * `render cornell` burnt 7.4 s of processor time for 2.2 s of work, and under load a spinning
 * thread took the core the caller needed (`solve cornell`, 2 threads, 9.9 s wall against 1.8 s
 * with one). Between loops the workers sleep on a condition variable and use no processor.
 *
 * The caller takes part; indices are handed out in order from a shared counter, so a loop whose
 * iterations write disjoint results gives the same bits for any thread count. A worker that
 * has not woken up by the time the indices run out is not waited for. */
#ifndef RAD_CORE_TEAM_H
#define RAD_CORE_TEAM_H

#include "core/context.h"

/* One iteration: `index` in [0, count), `worker` in [0, rad_thread_count) (0 is the caller). */
typedef void (*rad_team_task)(void *user, long index, int worker);

/* Runs task(user, i, worker) for every i in [0, count) on the context's threads and returns
 * when all are done. The workers are started on first use and kept until the context is
 * destroyed. Runs everything on the calling thread when the context asks for one thread, when
 * count < 2, when called from inside a parallel loop (OpenMP or this one), when the threads
 * cannot be started, or in a process forked after they were (it has none of them). */
void rad_team_for(rad_context *ctx, long count, rad_team_task task, void *user);

/* Stops and joins the workers (rad_context_destroy). */
void rad_team_destroy(rad_context *ctx);

#endif
