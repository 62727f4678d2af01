/*
** Output files already there: is one whole, as a finished write leaves it
** (`sumi render --resume` skips a frame or tile whose file is)? sumi's own
** writes are renamed into place only when complete (io/image.h), but a
** file can still be cut short after: a copy broken off, a full disk
** under a sync, a node that died before its data reached a network disk.
*/
#ifndef io_outfile_h
#define io_outfile_h

/* 1 when the file at path is whole for its format (by its extension):
**   png        libpng reads every row and the chunks to IEND, checksums too
**   tif        every strip, tile and tag value its directories point to
**              lies inside the file, and every row reads
**   exr, jpg   every row reads through OpenImageIO with no complaint (a
**              JPEG cut short reads grey-filled, with a warning)
**   svg        it ends with the closing tag sumi writes
** A band of rows is read at a time, so a file of any size costs a band of
** memory. Anything else (missing, not a regular file, another format
** under the name) is 0. */
int outfile_complete(const char *path);

#endif
