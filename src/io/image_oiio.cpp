/*
** The OpenImageIO bridge (C++17): writes and reads one image through OIIO
** and exposes both as a C function table, sumi_oiio_api(). Built alone as
** libsumi_oiio.so and dlopen'ed by image.c; see image_oiio.h for the
** contract. Every entry point catches every exception and turns it into a
** 0 result and a message.
**
** Per-format settings live here and only here:
**   PNG   zlib level SUMI_OIIO_PNG_LEVEL with no row filter (OIIO's
**         default, level 6 with adaptive filters, costs ~5x the time)
**   JPEG  quality 95 unless asked, 4:4:4 chroma (thin coloured ink lines
**         bleed under 4:2:0 subsampling)
**   TIFF  deflate ("zip"); EXR zip; both with a fixed DateTime
** and, for all, "oiio:UnassociatedAlpha" = 1 and no dithering.
*/
#include "image_oiio.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/oiioversion.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

/* zlib level for PNG. A toon-like 1920x1080 RGB frame, measured in OIIO
** alone: level 2 unfiltered ~8 ms, 46 KB; level 6 unfiltered ~17 ms, 20 KB;
** level 6 with adaptive filters (OIIO's default) ~39 ms, 15 KB. Speed wins:
** frames are written every render, and the files stay small. */
#define SUMI_OIIO_PNG_LEVEL 2
/* libpng's PNG_FILTER_NONE bit: write every row unfiltered. (0, OIIO's
** default for "png:filter", leaves libpng's adaptive choice on.) */
#define SUMI_OIIO_PNG_FILTER_NONE 8
#define SUMI_OIIO_JPEG_QUALITY 95
/* TIFF and EXR writers stamp the current time unless given one; a fixed
** stamp keeps "same scene, same bytes" true across runs. */
#define SUMI_OIIO_DATETIME "1970:01:01 00:00:00"

/* OIIO 2.4's PNG reader leaks its error string when libpng longjmps out of
** a truncated file (in PNGInput::PngReadCallback). Not ours to fix: under
** AddressSanitizer, what OIIO allocates while a LeakScope lives is not
** reported. Our own allocations happen outside these scopes. */
struct LeakScope {
#if defined(__SANITIZE_ADDRESS__)
  LeakScope() { __lsan_disable(); }
  ~LeakScope() { __lsan_enable(); }
#else
  LeakScope() {}
#endif
  LeakScope(const LeakScope &) = delete;
  LeakScope &operator=(const LeakScope &) = delete;
};

/* Copy msg into err (always terminated, truncated to fit). */
static void set_err(char *err, size_t errlen, const std::string &msg) {
  if (!err || errlen == 0) return;
  std::snprintf(err, errlen, "%s", msg.c_str());
}

/* OIIO's messages can span lines; keep the first, trimmed, for one-line
** diagnostics. */
static std::string first_line(std::string s) {
  size_t nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s.empty() ? std::string("unknown OpenImageIO error") : s;
}

static TypeDesc to_typedesc(int type) {
  switch (type) {
  case SUMI_OIIO_UINT8: return TypeDesc::UINT8;
  case SUMI_OIIO_UINT16: return TypeDesc::UINT16;
  case SUMI_OIIO_HALF: return TypeDesc::HALF;
  case SUMI_OIIO_FLOAT: return TypeDesc::FLOAT;
  case SUMI_OIIO_INT32: return TypeDesc::INT32;
  default: return TypeDesc::UNKNOWN;
  }
}

/* The class a file's pixel type is delivered in when the caller has no
** preference (see image_oiio.h). */
static int native_class(TypeDesc t) {
  switch (t.basetype) {
  case TypeDesc::UINT8: case TypeDesc::INT8: return SUMI_OIIO_UINT8;
  case TypeDesc::UINT16: case TypeDesc::INT16: return SUMI_OIIO_UINT16;
  case TypeDesc::UINT32: case TypeDesc::INT32: return SUMI_OIIO_INT32;
  default: return SUMI_OIIO_FLOAT;
  }
}

/* Lower-case extension of path's last component, without the dot. */
static std::string extension_of(const char *path) {
  const char *slash = std::strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  const char *dot = std::strrchr(base, '.');
  std::string ext = dot ? dot + 1 : "";
  for (char &c : ext) c = (char)std::tolower((unsigned char)c);
  return ext;
}

/* Per-format attributes; only those of the file's own format, since some
** writers copy unknown attributes into the header as metadata. */
static void set_format_attributes(ImageSpec &spec, const std::string &ext, int quality) {
  if (ext == "png") {
    spec.attribute("png:compressionLevel", SUMI_OIIO_PNG_LEVEL);
    spec.attribute("png:filter", SUMI_OIIO_PNG_FILTER_NONE);
  } else if (ext == "jpg" || ext == "jpeg") {
    int q = quality > 0 ? std::min(quality, 100) : SUMI_OIIO_JPEG_QUALITY;
    spec.attribute("Compression", "jpeg:" + std::to_string(q));
    spec.attribute("jpeg:subsampling", "4:4:4");
  } else if (ext == "tif" || ext == "tiff" || ext == "exr") {
    spec.attribute("Compression", "zip");
    spec.attribute("DateTime", SUMI_OIIO_DATETIME);
  }
}

static ImageSpec make_spec(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w) {
  int ftype = w && w->file_type ? w->file_type : px->type;
  ImageSpec spec(px->width, px->height, px->channels, to_typedesc(ftype));
  if (w && w->channel_names) {
    for (int c = 0; c < px->channels; c++) spec.channelnames[c] = w->channel_names[c];
  } else if (px->channels == 1) {
    spec.channelnames[0] = "Y";
  } else if (px->channels == 2) {
    spec.channelnames[0] = "Y";
    spec.channelnames[1] = "A";
  }
  spec.alpha_channel = px->alpha_channel;
  spec.z_channel = -1;
  for (int c = 0; c < px->channels; c++)
    if (spec.channelnames[c] == "Z") spec.z_channel = c;
  spec.attribute("oiio:UnassociatedAlpha", 1);
  spec.attribute("oiio:dither", 0);
  if (w && w->colorspace) spec.attribute("oiio:ColorSpace", w->colorspace);
  set_format_attributes(spec, extension_of(path), w ? w->quality : 0);
  if (w && w->full_width > 0) {   /* a tile of a larger image */
    spec.x = w->x;
    spec.y = w->y;
    spec.full_x = spec.full_y = 0;
    spec.full_width = w->full_width;
    spec.full_height = w->full_height;
  }
  if (w && w->description) spec.attribute("ImageDescription", w->description);
  return spec;
}

/* An open ImageOutput and what writing it needs. */
struct SumiOiioStream {
  std::unique_ptr<ImageOutput> out;
  TypeDesc mem;
  int y0;                            /* the data window's first row: OIIO counts rows from it */
};

/* Create the file for px (size and type; data not read) with w's settings. */
static SumiOiioStream *open_impl(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w,
                                 char *err, size_t errlen) {
  TypeDesc mem = to_typedesc(px->type);
  if (mem == TypeDesc::UNKNOWN || px->width <= 0 || px->height <= 0 || px->channels <= 0) {
    set_err(err, errlen, "bad pixel description");
    return nullptr;
  }
  std::unique_ptr<ImageOutput> out = ImageOutput::create(path);
  if (!out) {
    set_err(err, errlen, first_line(OIIO::geterror()));
    return nullptr;
  }
  ImageSpec spec = make_spec(path, px, w);
  if (!out->open(path, spec)) {
    set_err(err, errlen, first_line(out->geterror()));
    return nullptr;
  }
  return new SumiOiioStream{std::move(out), mem, spec.y};
}

static int rows_impl(SumiOiioStream *s, int y0, int y1, const void *rows, char *err, size_t errlen) {
  if (s->out->write_scanlines(s->y0 + y0, s->y0 + y1, 0, s->mem, rows)) return 1;
  set_err(err, errlen, first_line(s->out->geterror()));
  return 0;
}

/* Finish the file and free s. */
static int close_impl(SumiOiioStream *s, char *err, size_t errlen) {
  std::unique_ptr<SumiOiioStream> owned(s);
  if (s->out->close()) return 1;
  set_err(err, errlen, first_line(s->out->geterror()));
  return 0;
}

static int write_impl(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w,
                      char *err, size_t errlen) {
  SumiOiioStream *s = open_impl(path, px, w, err, errlen);
  if (!s) return 0;
  bool ok = s->out->write_image(s->mem, px->data);
  std::string msg = ok ? std::string() : s->out->geterror();
  if (!close_impl(s, err, errlen)) return 0;
  if (!ok) set_err(err, errlen, first_line(msg));
  return ok ? 1 : 0;
}

/* Process-wide settings, set to the same values before each read.
** OpenImageIO's bounds, which its readers check on a header before they
** allocate: the image at its widest type (double). EXR through OpenEXR's
** core C library, which checks a header against the file as it reads it:
** the C++ reader allocates each attribute at the size its header states
** (a fuzzed 700-byte file asked for 1.8 GB) and its decompression buffers
** by a row's width as the file opens (8388620 x 8 pixels: 1.6 GB). */
static void set_library_limits(const SumiOiioLimits *lim) {
  OIIO::attribute("openexr:core", 1);
  OIIO::attribute("limits:channels", lim->channels);
  OIIO::attribute("limits:imagesize_MB", (int)std::max(1LL, lim->values * 8 >> 20));
}

static int read_impl(const char *path, int want, const SumiOiioLimits *lim, SumiOiioPixels *px,
                     char *err, size_t errlen) {
  std::memset(px, 0, sizeof *px);
  set_library_limits(lim);
  ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<ImageInput> in;
  {
    LeakScope scope;
    in = ImageInput::open(path, &config);
  }
  if (!in) {
    set_err(err, errlen, first_line(OIIO::geterror()));
    return SUMI_OIIO_NOT_IMAGE;
  }
  const ImageSpec &spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    set_err(err, errlen, "unsupported image shape (" + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + ", " +
                             std::to_string(spec.nchannels) + " channels)");
    return SUMI_OIIO_NOT_IMAGE;
  }
  long long npix = (long long)spec.width * spec.height;
  if (npix > lim->pixels || spec.width > lim->side || spec.height > lim->side ||
      spec.nchannels > lim->channels || npix * spec.nchannels > lim->values) {
    px->width = spec.width;
    px->height = spec.height;
    px->channels = spec.nchannels;
    set_err(err, errlen, "header asks for " + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + " pixels of " +
                             std::to_string(spec.nchannels) + " channels");
    return SUMI_OIIO_TOO_LARGE;
  }
  int type = want ? want : native_class(spec.format);
  TypeDesc td = to_typedesc(type);
  size_t bytes = (size_t)npix * (size_t)spec.nchannels * td.size();
  void *data = std::malloc(bytes);
  if (!data) {
    set_err(err, errlen, "out of memory reading " + std::to_string(bytes) + " bytes");
    return SUMI_OIIO_CORRUPT;
  }
  px->data = data; /* owned by px from here, so the exception path frees it */
  bool ok;
  {
    LeakScope scope;
    ok = in->read_image(0, 0, 0, spec.nchannels, td, data);
  }
  if (!ok) {
    std::free(data);
    px->data = nullptr;
    set_err(err, errlen, first_line(in->geterror()));
    in->close();
    return SUMI_OIIO_CORRUPT;
  }
  px->width = spec.width;
  px->height = spec.height;
  px->channels = spec.nchannels;
  px->type = type;
  px->alpha_channel = spec.alpha_channel;
  std::snprintf(px->format, sizeof px->format, "%s", in->format_name());
  px->x = spec.x;
  px->y = spec.y;
  px->full_width = spec.full_width;
  px->full_height = spec.full_height;
  std::snprintf(px->description, sizeof px->description, "%s",
                spec.get_string_attribute("ImageDescription").c_str());
  in->close();
  (void)in->geterror(); /* drop warnings so OIIO does not print them at exit */
  return SUMI_OIIO_OK;
}

/* Rows read at a time by complete_impl. */
#define SUMI_OIIO_CHECK_ROWS 64

static int complete_impl(const char *path, char *err, size_t errlen) {
  std::unique_ptr<ImageInput> in;
  {
    LeakScope scope;
    in = ImageInput::open(path);
  }
  if (!in) {
    set_err(err, errlen, first_line(OIIO::geterror()));
    return 0;
  }
  const ImageSpec &spec = in->spec();
  int band = spec.tile_width > 0 ? std::max(spec.tile_height, 1) : SUMI_OIIO_CHECK_ROWS;
  int zend = spec.z + std::max(spec.depth, 1);
  std::vector<float> buf((size_t)spec.width * (size_t)band * (size_t)std::max(spec.depth, 1) *
                         (size_t)spec.nchannels);
  bool ok = true;
  for (int y = spec.y; ok && y < spec.y + spec.height; y += band) {
    int yend = std::min(y + band, spec.y + spec.height);
    LeakScope scope;
    ok = spec.tile_width > 0 ? in->read_tiles(0, 0, spec.x, spec.x + spec.width, y, yend, spec.z, zend, 0,
                                              spec.nchannels, TypeDesc::FLOAT, buf.data())
                             : in->read_scanlines(0, 0, y, yend, 0, 0, spec.nchannels, TypeDesc::FLOAT,
                                                  buf.data());
  }
  /* a reader that made do (libjpeg grey-fills a file cut short, with a
  ** warning) leaves a message: that too is no whole file */
  std::string msg = in->geterror();
  if (!msg.empty()) ok = false;
  if (!ok) set_err(err, errlen, msg.empty() ? "a read failed" : first_line(msg));
  in->close();
  (void)in->geterror();
  return ok ? 1 : 0;
}

/* ---- the C boundary: nothing thrown gets past these ------------------- */

static int bridge_read(const char *path, int want, const SumiOiioLimits *limits,
                       SumiOiioPixels *px, char *err, size_t errlen) {
  try {
    return read_impl(path, want, limits, px, err, errlen);
  } catch (const std::exception &e) {
    set_err(err, errlen, std::string("OpenImageIO failed: ") + e.what());
  } catch (...) {
    set_err(err, errlen, "OpenImageIO failed with an unknown exception");
  }
  std::free(px->data);
  px->data = nullptr;
  return SUMI_OIIO_CORRUPT;
}

/* Run f, turning any exception into a 0 result (or fail) and a message. */
template <typename R, typename F>
static R guarded(R fail, char *err, size_t errlen, F f) {
  try {
    return f();
  } catch (const std::exception &e) {
    set_err(err, errlen, std::string("OpenImageIO failed: ") + e.what());
  } catch (...) {
    set_err(err, errlen, "OpenImageIO failed with an unknown exception");
  }
  return fail;
}

static int bridge_write(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w,
                        char *err, size_t errlen) {
  return guarded(0, err, errlen, [&] { return write_impl(path, px, w, err, errlen); });
}

static SumiOiioStream *bridge_stream_open(const char *path, const SumiOiioPixels *px,
                                          const SumiOiioWrite *w, char *err, size_t errlen) {
  return guarded<SumiOiioStream *>(nullptr, err, errlen,
                                   [&] { return open_impl(path, px, w, err, errlen); });
}

static int bridge_stream_rows(SumiOiioStream *s, int y0, int y1, const void *rows, char *err,
                              size_t errlen) {
  return guarded(0, err, errlen, [&] { return rows_impl(s, y0, y1, rows, err, errlen); });
}

static int bridge_stream_close(SumiOiioStream *s, char *err, size_t errlen) {
  return guarded(0, err, errlen, [&] { return close_impl(s, err, errlen); });
}

static int bridge_complete(const char *path, char *err, size_t errlen) {
  return guarded(0, err, errlen, [&] { return complete_impl(path, err, errlen); });
}

extern "C" const SumiOiioApi *sumi_oiio_api(void) {
  static const SumiOiioApi api = {
    SUMI_OIIO_API_VERSION, OIIO_VERSION_STRING, bridge_write, bridge_read,
    bridge_stream_open, bridge_stream_rows, bridge_stream_close, bridge_complete,
  };
  return &api;
}
