/* ras_job.c — see ras_job.h. */
#include "ras_job.h"

#include <errno.h>    /* errno, EINTR */
#include <fcntl.h>    /* fcntl, FD_CLOEXEC */
#include <poll.h>     /* poll */
#include <pthread.h>  /* pthread_create, pthread_cond_timedwait */
#include <signal.h>   /* kill, signal, SIGKILL */
#include <stdlib.h>   /* calloc, free, getenv, strtod */
#include <sys/wait.h> /* waitpid */
#include <time.h>     /* clock_gettime */
#include <unistd.h>   /* fork, pipe, read, _exit */

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

/* ------------------------------------------------------------------------ */
/* In a child process                                                        */

static double now_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Collects the child's bytes until it closes its end, the time is up or
 * there are too many; the status to report (DONE means all was read). */
static ras_job_child_status child_collect(int fd, double seconds, size_t max_bytes,
                                          unsigned char **out, size_t *len) {
    double deadline = now_seconds() + seconds;
    size_t cap = 0;
    *out = NULL;
    *len = 0;
    for (;;) {
        double left = deadline - now_seconds();
        if (left <= 0) return RAS_JOB_CHILD_LATE;
        struct pollfd p = {fd, POLLIN, 0};
        int ready = poll(&p, 1, left > 3600 ? 3600 * 1000 : (int)(left * 1000) + 1);
        if (ready < 0 && errno != EINTR) return RAS_JOB_CHILD_NO_PROCESS;
        if (ready <= 0) continue;
        if (*len == cap) {
            size_t grown = cap ? 2 * cap : 1u << 16;
            if (grown > max_bytes + 1) grown = max_bytes + 1;
            unsigned char *bigger = grown > cap ? realloc(*out, grown) : NULL;
            if (!bigger) return *len > max_bytes ? RAS_JOB_CHILD_TOO_BIG : RAS_JOB_CHILD_NO_PROCESS;
            *out = bigger;
            cap = grown;
        }
        ssize_t n = read(fd, *out + *len, cap - *len);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return RAS_JOB_CHILD_NO_PROCESS;
        if (n == 0) return RAS_JOB_CHILD_DONE;
        *len += (size_t)n;
        if (*len > max_bytes) return RAS_JOB_CHILD_TOO_BIG;
    }
}

ras_job_child_status ras_job_run_child(ras_job_child_fn fn, void *arg, double seconds,
                                       size_t max_bytes, unsigned char **out, size_t *len,
                                       int *exit_status, int *signal_number) {
    *out = NULL;
    *len = 0;
    *exit_status = 0;
    *signal_number = 0;
    int pipe_fd[2];
    /* Close-on-exec, so a program the parent starts later holds no end. */
    if (pipe(pipe_fd) != 0) return RAS_JOB_CHILD_NO_PROCESS;
    fcntl(pipe_fd[0], F_SETFD, FD_CLOEXEC);
    fcntl(pipe_fd[1], F_SETFD, FD_CLOEXEC);
    pid_t pid = fork();
    if (pid < 0) {
        close(pipe_fd[0]);
        close(pipe_fd[1]);
        return RAS_JOB_CHILD_NO_PROCESS;
    }
    if (pid == 0) {
        close(pipe_fd[0]);
        /* A crash must end the child: handlers inherited from the parent
         * (a test framework's longjmp, a clean-up of the parent's files)
         * would run the parent's code in it instead. */
        static const int fatal[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT,
                                    SIGINT,  SIGTERM, SIGHUP, SIGPIPE};
        for (size_t i = 0; i < sizeof fatal / sizeof *fatal; i++) signal(fatal[i], SIG_DFL);
        /* _exit: no atexit handlers, stdio flushes or leak reports of the
         * parent's state run twice. */
        _exit(fn(arg, pipe_fd[1]));
    }
    close(pipe_fd[1]);
    ras_job_child_status st = child_collect(pipe_fd[0], seconds, max_bytes, out, len);
    close(pipe_fd[0]);
    if (st != RAS_JOB_CHILD_DONE) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (st == RAS_JOB_CHILD_DONE && WIFSIGNALED(status)) st = RAS_JOB_CHILD_CRASHED;
    if (WIFSIGNALED(status)) *signal_number = WTERMSIG(status);
    if (WIFEXITED(status)) *exit_status = WEXITSTATUS(status);
    if (st != RAS_JOB_CHILD_DONE) {
        free(*out);
        *out = NULL;
        *len = 0;
    }
    return st;
}
