/* The output lock and the file checks behind rs_io_output_guard (output_guard.f90).

   A run holds an advisory lock (flock) on "<output>.lock" for as long as it writes the output:
   a second run of the same path finds it taken and stops before it touches anything, and
   --merge finds a running sweep's lock taken. flock is released by the kernel when the
   process ends, however it ends, so a killed run leaves no stale lock (at most the empty lock
   file, which the next run takes over). */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

enum { lock_taken = -1, lock_error = -2, lock_unsupported = -3 };

static void put_message(char *message, int length, const char *text)
{
    if (length <= 0) return;
    snprintf(message, (size_t)length, "%s", text);
}

/* Take the lock file `lock_path` (created if missing) and write into it who holds it: `what`,
   the process and the host. Returns the descriptor to keep (>= 0), lock_taken with the
   holder's text in `message`, lock_error or lock_unsupported with the system's reason in
   `message`. */
int rs_output_lock(const char *lock_path, const char *what, char *message, int message_length)
{
    char host[256] = "an unknown host", holder[1024];
    gethostname(host, sizeof host - 1);
    host[sizeof host - 1] = '\0';
    snprintf(holder, sizeof holder, "%s, process %ld on %s", what, (long)getpid(), host);
    put_message(message, message_length, "");
    for (int attempt = 0; attempt < 8; ++attempt) {
        struct stat opened, named;
        const int   fd = open(lock_path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) {
            put_message(message, message_length, strerror(errno));
            return lock_error;
        }
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int failure = errno;
            if (failure == EWOULDBLOCK) {
                const ssize_t n = read(fd, message, message_length > 0 ? message_length - 1 : 0);
                if (n >= 0 && message_length > 0) message[n] = '\0';
                close(fd);
                return lock_taken;
            }
            close(fd);
            put_message(message, message_length, strerror(failure));
            return (failure == ENOLCK || failure == EINVAL || failure == EOPNOTSUPP)
                       ? lock_unsupported
                       : lock_error;
        }
        /* The holder before us may have removed the file between our open and our lock: then
           we hold a lock on a file nobody else will see. Take the one the name points to. */
        if (fstat(fd, &opened) != 0 || stat(lock_path, &named) != 0 ||
            opened.st_ino != named.st_ino || opened.st_dev != named.st_dev) {
            close(fd);
            continue;
        }
        if (ftruncate(fd, 0) == 0) {
            const size_t  length  = strlen(holder);
            const ssize_t written = write(fd, holder, length);
            (void)written; /* the text is for messages only */
        }
        return fd;
    }
    put_message(message, message_length, "the lock file kept changing under this run");
    return lock_error;
}

/* Give the lock back: the file is removed first, while it is still held. */
void rs_output_unlock(int fd, const char *lock_path)
{
    if (fd < 0) return;
    unlink(lock_path);
    close(fd);
}

/* 1 if `a` and `b` name the same existing file, else 0. */
int rs_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* What is at `path`: 0 nothing, 1 a directory, 2 a regular file starting with HDF5's
   signature, 3 another regular file, 4 something else (a FIFO, a device, ...). */
int rs_file_kind(const char *path)
{
    static const unsigned char signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    unsigned char              head[8];
    struct stat                st;
    if (stat(path, &st) != 0) return 0;
    if (S_ISDIR(st.st_mode)) return 1;
    if (!S_ISREG(st.st_mode)) return 4;
    const int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 3;
    const ssize_t n = read(fd, head, sizeof head);
    close(fd);
    return (n == (ssize_t)sizeof head && memcmp(head, signature, sizeof head) == 0) ? 2 : 3;
}
