/* ras_job.c — see ras_job.h. */
#include "ras_job.h"

#include <pthread.h> /* pthread_create, pthread_cond_timedwait */
#include <stdlib.h>  /* calloc, free, getenv, strtod */
#include <time.h>    /* clock_gettime */

typedef struct job {
    ras_job_fn fn;
    ras_job_discard_fn discard;
    void *arg, *result;
    bool done, abandoned;
    pthread_mutex_t lock;
    pthread_cond_t finished;
} job;

static void job_free(job *j) {
    pthread_mutex_destroy(&j->lock);
    pthread_cond_destroy(&j->finished);
    free(j);
}

static void *job_thread(void *p) {
    job *j = p;
    void *result = j->fn(j->arg);
    pthread_mutex_lock(&j->lock);
    bool abandoned = j->abandoned;
    j->result = result;
    j->done = true;
    pthread_cond_signal(&j->finished);
    pthread_mutex_unlock(&j->lock);
    if (abandoned) { /* the caller gave up on it: nobody takes the result */
        j->discard(result, j->arg);
        job_free(j);
    }
    return NULL;
}

bool ras_job_run(ras_job_fn fn, void *arg, ras_job_discard_fn discard, size_t stack,
                 double seconds, void **result) {
    job *j = calloc(1, sizeof *j);
    if (!j) { /* no room for the bookkeeping: run it here, unlimited */
        *result = fn(arg);
        return true;
    }
    j->fn = fn;
    j->discard = discard;
    j->arg = arg;
    pthread_mutex_init(&j->lock, NULL);
    pthread_cond_init(&j->finished, NULL);
    pthread_attr_t attr;
    pthread_t thread;
    bool threaded = pthread_attr_init(&attr) == 0;
    if (threaded) {
        threaded = (!stack || pthread_attr_setstacksize(&attr, stack) == 0) &&
                   pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED) == 0 &&
                   pthread_create(&thread, &attr, job_thread, j) == 0;
        pthread_attr_destroy(&attr);
    }
    if (!threaded) {
        *result = fn(arg);
        job_free(j);
        return true;
    }
    struct timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    deadline.tv_sec += (time_t)seconds;
    deadline.tv_nsec += (long)((seconds - (double)(time_t)seconds) * 1e9);
    if (deadline.tv_nsec >= 1000000000L) deadline.tv_sec++, deadline.tv_nsec -= 1000000000L;
    pthread_mutex_lock(&j->lock);
    while (!j->done)
        if (pthread_cond_timedwait(&j->finished, &j->lock, &deadline) != 0) break;
    bool done = j->done;
    if (!done) j->abandoned = true; /* the thread frees the job when it ends */
    pthread_mutex_unlock(&j->lock);
    if (!done) return false;
    *result = j->result;
    job_free(j);
    return true;
}

double ras_job_seconds(const char *name, double fallback) {
    const char *v = getenv(name);
    double s = v ? strtod(v, NULL) : 0;
    return s > 0 ? s : fallback;
}
