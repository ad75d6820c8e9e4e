/* ras_io.h — files in and out, safely.
 *
 * Inputs: only regular files are read. ras_io_open_input opens without
 * blocking (a FIFO given as a model would otherwise wait forever for a
 * writer) and checks the type with fstat: a FIFO, a device, a socket or a
 * folder is refused at once, with the type named.
 *
 * Outputs: ras_io_write_atomic writes a finished byte buffer (an encoded PNG,
 * a report) so that the target is either the complete new file or what was
 * there before, never a truncated mix:
 *   1. create a short temporary file beside the target, ".NAME-XXXXXX"
 *      (NAME cut so the whole name stays within 255 bytes), with the mode of
 *      the file it replaces (a new file: 0666 & ~umask);
 *   2. write every byte (each write checked; EINTR and short writes retried),
 *      fsync, close (checked: NFS reports errors there);
 *   3. read the file back and compare it with the buffer (not on tmpfs or
 *      ramfs, where it would read the very pages just written), then let the
 *      caller's verify callback decode it;
 *   4. rename over the target and fsync the folder.
 * Any failure unlinks the temporary file, leaves the target untouched, and
 * says which file and why (e.g. "No space left on device"). While the
 * temporary file exists, SIGINT, SIGTERM and SIGHUP remove it before the
 * process dies as it would have, and SIGXFSZ is ignored so a file-size limit
 * comes back as the write error EFBIG instead of a kill.
 * common/ never prints: errors come back in a ras_error.
 */
#ifndef RAS_IO_H
#define RAS_IO_H

#include "ras_error.h"

#include <stddef.h> /* size_t */
#include <signal.h> /* sigset_t */
#include <stdio.h>  /* FILE */
#include <time.h>   /* time_t */

/* Longest file name (path) the programs accept on the command line, in bytes
 * without the NUL: longer ones are refused by name, never silently cut. */
#define RAS_IO_MAX_PATH 1023

/* Opens `path` for reading if it is a regular file: returns the descriptor
 * (blocking mode, close-on-exec), or -1 with `why` set to a short reason
 * ("No such file or directory", "Permission denied", "expected a regular
 * file, got a FIFO", ...) for the caller to put into its own message. */
int ras_io_open_input(const char *path, char *why, size_t why_size);

/* Reads the whole regular file into a malloc'ed buffer with a NUL after the
 * last byte (the caller frees it); *len is the byte count. More than
 * max_bytes is refused without reading it. NULL and err set on failure,
 * worded "could not read WHAT 'PATH': REASON". */
void *ras_io_read_file(const char *path, const char *what, size_t max_bytes, size_t *len,
                       ras_error *err);

/* Checks that a written file decodes: gets the bytes read back. */
typedef bool (*ras_io_verify_fn)(const void *data, size_t len, void *ctx, ras_error *err);

/* Writes `len` bytes to `path` atomically (see above); `verify` may be NULL.
 * `what` names the file in messages ("image", "report"). */
bool ras_io_write_atomic(const char *path, const char *what, const void *data, size_t len,
                         ras_io_verify_fn verify, void *ctx, ras_error *err);

/* Write-protected targets (no write bit, or not writable by this user) are
 * refused by ras_io_write_atomic and ras_io_check_replace unless force is
 * set (the programs' --force). */
void ras_io_set_force(bool force);
/* True when `path` is new, or a file this run may replace; else false and
 * err naming the file, its mode and --force. `what` as in ras_io_write_atomic. */
bool ras_io_check_replace(const char *path, const char *what, ras_error *err);

/* Removes, in `dir`, the temporaries ras_io_write_atomic names
 * (".NAME-XXXXXX", NAME ending in an extension the programs write) that are
 * regular files of this user last written before this process started: what
 * a kill -9 (which no handler sees) left. ras_io_write_atomic calls it for
 * its target's folder. Returns how many it removed. */
int ras_io_remove_stale_temporaries(const char *dir);
/* When this process started (seconds since the epoch, from /proc), 0 when
 * unknown: what "left before this run" is measured against. */
time_t ras_io_process_start(void);

/* A temporary folder (templ ends in XXXXXX, as for mkdtemp) that a
 * SIGINT, SIGTERM or SIGHUP removes, with the files in it (it must stay
 * flat), before the process dies of the signal: held from its creation until
 * ras_io_temp_folder_release (one at a time; false with errno set when it
 * cannot be made). Renaming it into place and then releasing it is the
 * caller's commit. */
bool ras_io_temp_folder_create(char *templ);
void ras_io_temp_folder_release(void);
/* SIGINT, SIGTERM and SIGHUP held back (the old mask into *old, for
 * sigprocmask(SIG_SETMASK, old, NULL)) while a step must not be cut. */
void ras_io_cleanup_signals_block(sigset_t *old);

/* A text report (CSV, Markdown) written with stdio into memory, then to its
 * file with ras_io_write_atomic: ras_io_report_open gives the FILE* to
 * fprintf into (NULL when out of memory); ras_io_report_commit closes it and
 * writes the file, or, with path NULL, only discards it. */
typedef struct ras_io_report {
    FILE *f;
    char *buf;
    size_t len;
} ras_io_report;
FILE *ras_io_report_open(ras_io_report *r);
bool ras_io_report_commit(ras_io_report *r, const char *path, ras_error *err);

/* The folder of `path` ("." when it has none, "/" for a file at the root)
 * into `dir`, cut to `size`. */
void ras_io_folder_of(const char *path, char *dir, size_t size);

/* Checks a file name given on the command line: not longer than
 * RAS_IO_MAX_PATH. `option` names it in the message ("--reference"). */
bool ras_io_path_fits(const char *option, const char *path, ras_error *err);

/* The deepest nesting in a text: JSON brackets ({ and [, outside strings),
 * braces, and XML elements (<a><b/></a> is 2). Counting stops past `stop`
 * (the result is then stop + 1), and *at is set to the byte offset where the
 * nesting first went past it. Parsers that recurse per level (assimp's
 * rapidjson, cJSON, XML DOM destructors) are checked with it first. */
size_t ras_io_text_nesting(const char *text, size_t len, size_t stop, size_t *at);

#endif
