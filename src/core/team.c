/* team.c - the context's worker threads (team.h): a fixed set of POSIX threads that sleep on a
 * condition variable between loops and share a loop's indices through an atomic counter. */
#include "core/team.h"

#include <omp.h>
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <unistd.h>

typedef struct worker {
    pthread_t thread;
    struct rad_team *team;
    int index; /* 1 .. worker_count */
    unsigned long seen; /* the loops before it started: none of them is its */
} worker;

struct rad_team {
    rad_allocator allocator; /* the context's */
    pid_t owner;             /* the process whose threads these are (a forked child has none) */
    pthread_mutex_t lock;
    pthread_cond_t wake;     /* a new loop, or quit */
    pthread_cond_t finished; /* a worker left a loop */
    int worker_count;        /* threads started, not counting the caller */
    int busy;                /* a loop is running: a nested call runs alone */
    int quit;
    unsigned long generation; /* counts loops, so a worker sees each one once */
    /* The current loop; task is NULL once the caller has seen every index done. */
    rad_team_task task;
    void *user;
    long count;
    atomic_long next;
    int inside; /* workers running the current loop's indices */
    worker workers[];
};

static _Thread_local int in_team_worker;

static void run_indices(struct rad_team *team, rad_team_task task, void *user, long count,
                        int worker) {
    for (;;) {
        long i = atomic_fetch_add_explicit(&team->next, 1, memory_order_relaxed);
        if (i >= count) break;
        task(user, i, worker);
    }
}

static void *worker_main(void *argument) {
    const worker *me = argument;
    struct rad_team *team = me->team;
    in_team_worker = 1;
    pthread_mutex_lock(&team->lock);
    /* Not the generation now: the loop that started the team has counted itself already, and a
     * worker that took it as seen slept through it (a context's first loop ran on the caller
     * alone, all of it when it was the only one: shooting.c's rows of a small system). */
    unsigned long seen = me->seen;
    for (;;) {
        while (team->generation == seen && !team->quit) pthread_cond_wait(&team->wake, &team->lock);
        if (team->quit) break;
        seen = team->generation;
        if (!team->task) continue; /* woke after the loop was over */
        rad_team_task task = team->task;
        void *user = team->user;
        long count = team->count;
        team->inside++;
        pthread_mutex_unlock(&team->lock);
        run_indices(team, task, user, count, me->index);
        pthread_mutex_lock(&team->lock);
        if (--team->inside == 0) pthread_cond_signal(&team->finished);
    }
    pthread_mutex_unlock(&team->lock);
    return NULL;
}

/* Starts the workers (through the context's allocator, without recording an error: a team that
 * cannot start just leaves everything on the caller). */
static struct rad_team *team_start(rad_context *ctx, int workers) {
    size_t bytes = sizeof(struct rad_team) + (size_t)workers * sizeof(worker);
    struct rad_team *team = ctx->allocator.allocate(ctx->allocator.user, bytes);
    if (!team) return NULL;
    memset(team, 0, bytes);
    team->allocator = ctx->allocator;
    team->owner = getpid();
    if (pthread_mutex_init(&team->lock, NULL)) goto fail_lock;
    if (pthread_cond_init(&team->wake, NULL)) goto fail_wake;
    if (pthread_cond_init(&team->finished, NULL)) goto fail_finished;
    atomic_init(&team->next, 0);
    ctx->team = team;
    for (int w = 0; w < workers; ++w) {
        worker *one = &team->workers[team->worker_count];
        one->team = team;
        one->index = team->worker_count + 1;
        one->seen = team->generation;
        if (pthread_create(&one->thread, NULL, worker_main, one)) break;
        team->worker_count++;
    }
    return team;
fail_finished:
    pthread_cond_destroy(&team->wake);
fail_wake:
    pthread_mutex_destroy(&team->lock);
fail_lock:
    ctx->allocator.release(ctx->allocator.user, team);
    return NULL;
}

void rad_team_for(rad_context *ctx, long count, rad_team_task task, void *user) {
    const int threads = rad_thread_count(ctx);
    struct rad_team *team = ctx ? ctx->team : NULL;
    if (ctx && !team && threads > 1 && count > 1 && !in_team_worker && !omp_in_parallel())
        team = team_start(ctx, threads - 1);
    int alone = !team || !team->worker_count || count < 2 || in_team_worker || omp_in_parallel() ||
                team->owner != getpid();
    if (!alone) {
        pthread_mutex_lock(&team->lock);
        alone = team->busy;
        if (!alone) {
            team->busy = 1;
            team->task = task;
            team->user = user;
            team->count = count;
            atomic_store_explicit(&team->next, 0, memory_order_relaxed);
            team->generation++;
            pthread_cond_broadcast(&team->wake);
        }
        pthread_mutex_unlock(&team->lock);
    }
    if (alone) {
        for (long i = 0; i < count; ++i) task(user, i, 0);
        return;
    }
    run_indices(team, task, user, count, 0);
    /* Every index is taken; wait for the workers still running theirs. */
    pthread_mutex_lock(&team->lock);
    while (team->inside > 0) pthread_cond_wait(&team->finished, &team->lock);
    team->task = NULL;
    team->busy = 0;
    pthread_mutex_unlock(&team->lock);
}

void rad_team_destroy(rad_context *ctx) {
    struct rad_team *team = ctx ? ctx->team : NULL;
    if (!team) return;
    if (team->owner != getpid()) { /* a forked child: the threads are the parent's */
        team->allocator.release(team->allocator.user, team);
        ctx->team = NULL;
        return;
    }
    pthread_mutex_lock(&team->lock);
    team->quit = 1;
    pthread_cond_broadcast(&team->wake);
    pthread_mutex_unlock(&team->lock);
    for (int w = 0; w < team->worker_count; ++w) pthread_join(team->workers[w].thread, NULL);
    pthread_cond_destroy(&team->wake);
    pthread_cond_destroy(&team->finished);
    pthread_mutex_destroy(&team->lock);
    team->allocator.release(team->allocator.user, team);
    ctx->team = NULL;
}
