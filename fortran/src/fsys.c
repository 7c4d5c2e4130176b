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

static void remove_temp_and_die(int sig)
{
    if (temp_set) unlink(temp_path);
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
