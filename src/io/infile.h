/*
** Files a scene names (its includes, FOLD and crease patterns, meshes,
** images) are checked before they are read: each must be a regular file
** (not a directory, a device, a FIFO or a socket, which read forever or
** not at all) no larger than the cap for its kind.
*/
#ifndef io_infile_h
#define io_infile_h

#include <stddef.h>

/* The largest file of each kind sumi reads. */
#define INFILE_MAX_SOURCE (1LL << 30)   /* scene text: offsets into it are ints */
#define INFILE_MAX_FOLD (256LL << 20)   /* JSON, held whole, then ~10x in cJSON's tree */
#define INFILE_MAX_MESH (2LL << 30)     /* Assimp reads it whole */
#define INFILE_MAX_IMAGE (1LL << 30)    /* compressed; the pixel limit bounds what it unpacks to */

/* 1 when path names a regular file of at most max bytes. Otherwise 0 with
** why (n bytes) saying what it is: "is a directory", "is not a regular
** file (a character device)", "is 2.1 GB; the limit for a mesh is 2 GB"
** (kind: "a mesh"), or the system's reason ("No such file or directory"). */
int infile_check(const char *path, long long max, const char *kind, char *why, size_t n);

#endif
