/* POSIX file-system helpers for the Fortran side (module ringlube_fsys in fsys.f90).
 *
 * Fortran has no portable stat(2), O_EXCL creation or errno text; these few functions
 * give ringlube-solve what it needs to refuse unsafe outputs and to write results under
 * a unique temporary name. Every function takes NUL-terminated paths.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <pthread.h>
#include <signal.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

/* What `path` is, following symbolic links: 0 does not exist, 1 regular file,
 * 2 folder, 3 something else (device, FIFO, socket), -1 cannot tell (errno kept). */
int rl_file_kind(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        if (errno == ENOENT) return 0;
        return -1;
    }
    if (S_ISREG(st.st_mode)) return 1;
    if (S_ISDIR(st.st_mode)) return 2;
    return 3;
}

/* 1 when `path` itself is a symbolic link (lstat), else 0. */
int rl_is_symlink(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0 && S_ISLNK(st.st_mode);
}

/* 1 when both paths exist and name the same file (same device and inode, so hard
 * links, symbolic links and different spellings all count), else 0. */
int rl_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* The temporary file being written (empty when none), removed by the signal handler
 * that rl_remove_temp_on_signal installs. */
static char temp_path[4096];
static volatile sig_atomic_t temp_set = 0;

static void progress_interrupted(void);

static void remove_temp_and_die(int sig)
{
    if (temp_set) unlink(temp_path);
    progress_interrupted();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* On SIGINT, SIGTERM and SIGHUP, delete the temporary file being written (if any), then
 * end as the signal would have. For programs only: a library must not take signals. */
void rl_remove_temp_on_signal(void)
{
    signal(SIGINT, remove_temp_and_die);
    signal(SIGTERM, remove_temp_and_die);
    signal(SIGHUP, remove_temp_and_die);
}

/* Ctrl-C during a kernel call from Python (the f2py layer): the kernel polls
 * rl_interrupt_requested() at every crank step and returns an 'interrupted' error, so
 * `ringlube.run` and `ringlube run` stop within a step and write nothing. Python's own
 * SIGINT handler would only act once the call returns. Begin/end nest (a counter under a
 * mutex, for calls from several threads); the handler saved at the first begin is put back
 * at the last end. A SIGINT that was ignored stays ignored. */
static volatile sig_atomic_t interrupt_flag = 0;
static struct sigaction saved_int;
static int catch_depth = 0;
static pthread_mutex_t catch_mutex = PTHREAD_MUTEX_INITIALIZER;

static void note_interrupt(int sig)
{
    (void)sig;
    interrupt_flag = 1;
}

void rl_interrupt_catch_begin(void)
{
    pthread_mutex_lock(&catch_mutex);
    if (catch_depth++ == 0) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = note_interrupt;
        sigemptyset(&sa.sa_mask);
        interrupt_flag = 0;
        if (sigaction(SIGINT, &sa, &saved_int) == 0 && saved_int.sa_handler == SIG_IGN)
            sigaction(SIGINT, &saved_int, NULL);
    }
    pthread_mutex_unlock(&catch_mutex);
}

/* End a catch; returns 1 if SIGINT arrived since the outermost begin. */
int rl_interrupt_catch_end(void)
{
    int was;
    pthread_mutex_lock(&catch_mutex);
    was = interrupt_flag;
    if (catch_depth > 0 && --catch_depth == 0) sigaction(SIGINT, &saved_int, NULL);
    pthread_mutex_unlock(&catch_mutex);
    return was;
}

/* 1 once SIGINT arrived during a catch. */
int rl_interrupt_requested(void)
{
    return interrupt_flag;
}

/* Forget the temporary file `path` (it was renamed or removed). */
void rl_forget_temp(const char *path)
{
    if (temp_set && strcmp(path, temp_path) == 0) temp_set = 0;
}

/* A new, empty file named `base.<pid>.<random>.part` in base's folder, created with
 * O_CREAT | O_EXCL (so no other process can own the same name) and the permissions a
 * plain new file gets (0666 less the umask). Its name goes to `out` (capacity `outlen`,
 * NUL-terminated). Returns 0, or the errno of the failure (ENAMETOOLONG if `out` is
 * too small). */
int rl_make_temp(const char *base, char *out, int outlen)
{
    static uint64_t counter = 0;
    struct timespec ts;
    uint64_t x;
    int attempt, fd, n;

    clock_gettime(CLOCK_REALTIME, &ts);
    x = ((uint64_t)ts.tv_sec * 1000000007u) ^ (uint64_t)ts.tv_nsec ^ ((uint64_t)getpid() << 32);
    for (attempt = 0; attempt < 100; attempt++) {
        /* splitmix64 step: different names on every attempt and every call */
        x += 0x9e3779b97f4a7c15u + (++counter);
        uint64_t z = x;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
        z ^= z >> 31;
        n = snprintf(out, (size_t)outlen, "%s.%ld.%06llx.part", base, (long)getpid(),
                     (unsigned long long)(z & 0xffffffu));
        if (n < 0 || n >= outlen) return ENAMETOOLONG;
        temp_set = 0;
        if ((size_t)n < sizeof temp_path) memcpy(temp_path, out, (size_t)n + 1);
        fd = open(out, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            close(fd);
            temp_set = (size_t)n < sizeof temp_path;
            return 0;
        }
        if (errno != EEXIST) return errno;
    }
    return EEXIST;
}

/* errno as set by the last failing system call (0 if none since rl_clear_errno). */
int rl_errno(void) { return errno; }

void rl_clear_errno(void) { errno = 0; }

/* The text of an errno value, copied into `out` (capacity `outlen`, NUL-terminated). */
void rl_strerror(int code, char *out, int outlen)
{
    if (outlen <= 0) return;
    if (strerror_r(code, out, (size_t)outlen) != 0) snprintf(out, (size_t)outlen, "error %d", code);
}

/* Make a write beyond the file-size limit (ulimit -f) fail with EFBIG, reported as an
 * error like a full disk, instead of killing the process with SIGXFSZ (which the
 * gfortran runtime turns into a backtrace even when the shell ignores the signal). */
void rl_ignore_sigxfsz(void)
{
#ifdef SIGXFSZ
    signal(SIGXFSZ, SIG_IGN);
#endif
}

/* Progress of a long run on the terminal (ringlube-solve and `ringlube run` without -q).
 * The kernel notes the cycle it is in (rl_progress_cycle: 0 the warm-up) and the crank angle
 * of every step (rl_progress_step); once a run has lasted progress_after seconds, a line on
 * standard error, rewritten in place at most every progress_every seconds, says where it is
 * and about how long the cycle has left; the line is cleared when the run ends. Only when the
 * front end asked for it (rl_progress_enable) and standard error is a terminal: never in a
 * pipe, a log file, a batch of designs or a call from the Python API. A step costs one call
 * and, while enabled, one read of the monotonic clock. */
static const double progress_after = 2.0, progress_every = 0.5;
static int progress_wanted = 0, progress_active = 0, progress_shown = 0;
static int progress_cycle = 0, progress_max = 0;
static double progress_t0 = 0.0, progress_last = 0.0, progress_cycle_t0 = 0.0;
static double progress_cycle_s = 0.0, progress_psi0 = 0.0;

static double progress_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Ask for the progress line (on: 1) or not (0) in the runs that follow. */
void rl_progress_enable(int on) { progress_wanted = on != 0; }

/* A run of at most max_cycles cycles begins. */
void rl_progress_begin(int max_cycles)
{
    progress_active = progress_wanted && isatty(STDERR_FILENO);
    if (!progress_active) return;
    progress_t0 = progress_now();
    progress_last = progress_t0;
    progress_cycle_t0 = progress_t0;
    progress_cycle_s = 0.0;
    progress_cycle = 0;
    progress_psi0 = -1.0;
    progress_max = max_cycles;
    progress_shown = 0;
}

/* The run enters cycle icycle (0: the warm-up; the same cycle again: its re-warm). */
void rl_progress_cycle(int icycle)
{
    double t;
    if (!progress_active) return;
    t = progress_now();
    /* (the last whole cycle's time: what the next one will about take) */
    if (progress_cycle >= 1 && icycle > progress_cycle) progress_cycle_s = t - progress_cycle_t0;
    progress_cycle = icycle;
    progress_cycle_t0 = t;
    progress_psi0 = -1.0;
}

/* The step to crank angle psi [deg] is being solved. */
void rl_progress_step(double psi)
{
    double t, done, left;
    char line[160];
    int n;
    if (!progress_active) return;
    if (progress_psi0 < 0.0) progress_psi0 = psi;
    t = progress_now();
    if (t - progress_t0 < progress_after || t - progress_last < progress_every) return;
    progress_last = t;
    if (progress_cycle == 0) {
        left = psi > progress_psi0 ? (t - progress_cycle_t0) * (720.0 - psi) / (psi - progress_psi0) : -1.0;
        if (left >= 0.0)
            n = snprintf(line, sizeof line, "ringlube: warm-up, crank angle %.1f deg, about %.0f s to its end, "
                         "%.0f s so far", psi, left, t - progress_t0);
        else
            n = snprintf(line, sizeof line, "ringlube: warm-up, crank angle %.1f deg, %.0f s so far", psi,
                         t - progress_t0);
    } else {
        /* this cycle's remaining time from its pace so far (or the last cycle's time) */
        done = (psi - progress_psi0) / 720.0;
        left = -1.0;
        if (progress_cycle_s > 0.0) left = progress_cycle_s * (720.0 - psi) / 720.0;
        else if (done > 0.02) left = (t - progress_cycle_t0) * (720.0 - psi) / (psi - progress_psi0);
        if (left >= 0.0)
            n = snprintf(line, sizeof line,
                         "ringlube: cycle %d (at most %d), crank angle %.1f deg, about %.0f s to the cycle's end, "
                         "%.0f s so far",
                         progress_cycle, progress_max, psi, left, t - progress_t0);
        else
            n = snprintf(line, sizeof line, "ringlube: cycle %d (at most %d), crank angle %.1f deg, %.0f s so far",
                         progress_cycle, progress_max, psi, t - progress_t0);
    }
    if (n < 0) return;
    fprintf(stderr, "\r%-*s", progress_shown > n ? progress_shown : n, line);
    fflush(stderr);
    if (n > progress_shown) progress_shown = n;
}

/* The run ends (also on an error or Ctrl-C): the line, if shown, is cleared. */
void rl_progress_end(void)
{
    if (progress_active && progress_shown > 0) {
        fprintf(stderr, "\r%*s\r", progress_shown, "");
        fflush(stderr);
    }
    progress_active = 0;
    progress_shown = 0;
}

/* A signal ends the process with the line shown: end it, so that the shell's prompt starts on
 * a line of its own (write(2) only: called from a signal handler). */
static void progress_interrupted(void)
{
    if (progress_active && progress_shown > 0) {
        ssize_t w = write(STDERR_FILENO, "\n", 1);
        (void)w;
    }
}

/* CPU time the calling thread has used [s] (0 where the clock is missing): a distorted bore's
   team of threads (sectors.f90) tells from it whether a thread waiting awake kept its core. */
double rl_thread_cpu_seconds(void)
{
#ifdef CLOCK_THREAD_CPUTIME_ID
    struct timespec t;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) == 0) return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
#endif
    return 0.0;
}
