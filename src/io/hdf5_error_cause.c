/* The operating system's (or MPI-IO's) reason for the last failed HDF5 call, for the messages
   of rs_io_hdf5_file (issue 21 item 3: a full disk said only "H5Fflush failed"). HDF5 keeps
   the failing call's error stack until the next API call; the sec2 driver's innermost entry
   reads "... errno = 28, error message = 'No space left on device', ...", the MPI-IO driver's
   "MPI_File_write_at_all failed: <MPI_Error_string>". Only src/io/ calls HDF5. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <hdf5.h>

typedef struct {
    char *text;
    size_t size;
    int found;
} cause_t;

/* Copy at most size - 1 characters of `from` (up to `stop`, or its end) into cause->text. */
static void keep(cause_t *cause, const char *from, const char *stop)
{
    size_t n = stop ? (size_t)(stop - from) : strlen(from);
    if (n >= cause->size) n = cause->size - 1;
    memcpy(cause->text, from, n);
    cause->text[n] = '\0';
    cause->found = 1;
}

/* Walked from the innermost entry outwards: the first entry naming a system or MPI error. */
static herr_t visit(unsigned n, const H5E_error2_t *entry, void *data)
{
    cause_t *cause = (cause_t *)data;
    const char *desc = entry->desc, *at, *end;
    (void)n;
    if (cause->found || desc == NULL) return 0;
    at = strstr(desc, "error message = '");
    if (at != NULL) {
        at += strlen("error message = '");
        end = strchr(at, '\'');
        keep(cause, at, end);
        /* "No space left on device (errno 28)": the number as the driver gave it. */
        at = strstr(desc, "errno = ");
        if (at != NULL) {
            int number = 0;
            if (sscanf(at, "errno = %d", &number) == 1) {
                size_t used = strlen(cause->text);
                snprintf(cause->text + used, cause->size - used, " (errno %d)", number);
            }
        }
        return 0;
    }
    at = strstr(desc, "MPI_File");
    if (at != NULL) keep(cause, at, NULL);
    return 0;
}

/* Writes the cause of the last HDF5 failure into text (NUL-terminated, at most size bytes)
   and returns 1, or returns 0 (text empty) when the error stack names none. */
int rs_hdf5_error_cause(char *text, int size)
{
    cause_t cause;
    if (size <= 0) return 0;
    text[0] = '\0';
    cause.text = text;
    cause.size = (size_t)size;
    cause.found = 0;
    if (H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, visit, &cause) < 0) return 0;
    return cause.found;
}

/* Reserve `bytes` of disk for the file `path` (open as the HDF5 file `file`) from its end of
   allocated space (EOA), where HDF5 puts new chunks and metadata: posix_fallocate allocates the
   blocks, so the writes that follow cannot meet a full disk or a file-size limit, and a full
   disk is found before anything is extended (issue 21 item 3). What HDF5 does not use stays at
   the end of the file until rank 0 opens it alone at the end of the run (finish_result_file):
   closing it there truncates the file to its EOA (measured: the same file size as without
   the reservation). Returns 0, or the error number (ENOSPC, EFBIG, ...); 0 also where the
   file system cannot reserve (EOPNOTSUPP, EINVAL): then nothing is reserved. */
int rs_hdf5_reserve(hid_t file, const char *path, long long bytes)
{
    haddr_t eoa;
    int fd, status;
    /* A file-size limit (ulimit -f) sends SIGXFSZ, which would kill the run without a word;
       ignored, the call fails with EFBIG instead and the run says why. */
    signal(SIGXFSZ, SIG_IGN);
    if (bytes <= 0) return 0;
    fd = open(path, O_WRONLY);
    if (fd < 0) return errno;
    /* A file open with the MPI-IO driver answers no EOA query here (H5Fget_eoa fails); its
       flushes extend the file to the EOA, so from the file's size on nothing is allocated
       yet (what lies between the EOA and the size is reserved already). */
    if (H5Fget_eoa(file, &eoa) < 0) {
        struct stat st;
        if (fstat(fd, &st) != 0) {
            status = errno;
            close(fd);
            return status;
        }
        eoa = (haddr_t)st.st_size;
    }
    status = posix_fallocate(fd, (off_t)eoa, (off_t)bytes);
    close(fd);
    if (status == EOPNOTSUPP || status == EINVAL) return 0;
    return status;
}

/* The system's text for the error number `number`, with the number. */
void rs_error_text(int number, char *text, int size)
{
    const char *message;
    if (size <= 0) return;
    message = strerror(number);
    snprintf(text, (size_t)size, "%s (errno %d)", message ? message : "unknown error", number);
}
