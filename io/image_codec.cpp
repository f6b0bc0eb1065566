#include "io/image_codec.h"

#include <jerror.h>
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
// jpeglib.h needs size_t and FILE declared before it.
#include <jpeglib.h>

#include "core/error.h"
#include "io/png_inflate.h"

// libpng and libjpeg report errors by longjmp. Each function below that calls setjmp holds only
// plain data between setjmp and the library calls (no object with a destructor that a longjmp
// could skip); buffers are allocated by the C++ callers before, and freed by them after.

namespace vf {
namespace {

constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

bool isPng(const uint8_t* data, size_t size) { return size >= 8 && std::memcmp(data, kPngSignature, 8) == 0; }
bool isJpeg(const uint8_t* data, size_t size) { return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF; }

void checkPixelCount(uint64_t width, uint64_t height, const std::string& name, const std::string& what) {
  if (width == 0 || height == 0)
    throw Error(what + " " + name + " is " + std::to_string(width) + "x" + std::to_string(height) + ": an image needs pixels");
  if (width * height > kMaxImagePixels)
    throw Error(what + " " + name + " is " + std::to_string(width) + "x" + std::to_string(height) + " (" +
                std::to_string(width * height / 1000000) + " Mpx), more than the " +
                std::to_string(kMaxImagePixels / 1000000) + " Mpx a frame may have; refusing to allocate it");
}

// ---- PNG ---------------------------------------------------------------------------------------

struct PngState {
  const uint8_t* data = nullptr;
  size_t size = 0, pos = 0;
};

// libpng's error pointer: the message of the error that ended decoding or encoding.
struct PngError {
  char text[200] = {0};
};

void pngReadBytes(png_structp png, png_bytep out, size_t n) {
  auto* s = static_cast<PngState*>(png_get_io_ptr(png));
  if (n > s->size - s->pos) png_error(png, "the file ends early (truncated)");
  std::memcpy(out, s->data + s->pos, n);
  s->pos += n;
}

void pngOnError(png_structp png, png_const_charp message) {
  auto* e = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(e->text, sizeof e->text, "%s", message);
  png_longjmp(png, 1);
}

// Warnings concern ancillary chunks (bad sRGB profile, text); the pixels are unaffected.
void pngOnWarning(png_structp, png_const_charp) {}

struct PngRaw {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  bool has_trns = false;
};

class PngReader {
 public:
  PngReader(const uint8_t* data, size_t size, std::string name, std::string what)
      : name_(std::move(name)), what_(std::move(what)) {
    state_.data = data;
    state_.size = size;
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error_, pngOnError, pngOnWarning);
    if (png_) info_ = png_create_info_struct(png_);
    if (!png_ || !info_) {
      png_destroy_read_struct(&png_, &info_, nullptr);
      throw Error("cannot decode " + what_ + " " + name_ + ": out of memory");
    }
    png_set_read_fn(png_, &state_, pngReadBytes);
  }
  ~PngReader() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  // Reads the chunks up to the image data.
  ImageHeader readHeader() {
    if (!readInfo(png_, info_, &raw_)) fail();
    checkPixelCount(raw_.width, raw_.height, name_, what_);
    ImageHeader h;
    h.width = int(raw_.width);
    h.height = int(raw_.height);
    h.bits = raw_.bit_depth == 16 ? 16 : 8;
    switch (raw_.color_type) {  // as OpenCV's PngDecoder::readHeader counts channels
      case PNG_COLOR_TYPE_RGB:
      case PNG_COLOR_TYPE_PALETTE: h.channels = raw_.has_trns ? 4 : 3; break;
      case PNG_COLOR_TYPE_GRAY_ALPHA:
      case PNG_COLOR_TYPE_RGB_ALPHA: h.channels = 4; break;
      default: h.channels = 1;
    }
    header_ = h;
    return h;
  }

  // Grey output (1 channel of the stored depth, 1/2/4-bit expanded to 8).
  void readGrey(uint8_t* pixels) { readImage(pixels, false); }
  // RGBA output: palette and grey expanded, alpha added (0xFF / 0xFFFF) where the file has none.
  // Returns whether the file had alpha of its own (the caller then overwrites it).
  bool readRgba(uint8_t* pixels) { return readImage(pixels, true); }

 private:
  static bool readInfo(png_structp png, png_infop info, PngRaw* raw) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_user_limits(png, 1u << 20, 1u << 20);
    png_read_info(png, info);
    png_get_IHDR(png, info, &raw->width, &raw->height, &raw->bit_depth, &raw->color_type, nullptr, nullptr, nullptr);
    raw->has_trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    return true;
  }

  // Sets the transforms, checks the row size they give against `row_bytes`, reads every row
  // and the chunks after the image (a file cut after its pixels is refused too, as OpenCV does).
  static bool readRows(png_structp png, png_infop info, const PngRaw* raw, bool rgba, png_bytep* rows,
                       size_t row_bytes, bool* layout_ok) {
    if (setjmp(png_jmpbuf(png))) return false;
    const bool color = (raw->color_type & PNG_COLOR_MASK_COLOR) != 0;
    if (raw->color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (!color && raw->bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (raw->bit_depth == 16) png_set_swap(png);  // PNG is big-endian; x86 and Arm are not
    if (rgba) {
      if (!color) png_set_gray_to_rgb(png);
      const bool alpha = (raw->color_type & PNG_COLOR_MASK_ALPHA) != 0 ||
                         (raw->color_type == PNG_COLOR_TYPE_PALETTE && raw->has_trns);
      if (!alpha) png_set_filler(png, 0xFFFF, PNG_FILLER_AFTER);
    } else if (raw->color_type & PNG_COLOR_MASK_ALPHA) {
      png_set_strip_alpha(png);
    }
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    *layout_ok = png_get_rowbytes(png, info) == row_bytes;
    if (!*layout_ok) return true;
    png_read_image(png, rows);
    png_read_end(png, nullptr);
    return true;
  }

  bool readImage(uint8_t* pixels, bool rgba) {
    const size_t bytes_per_sample = header_.bits / 8;
    const size_t row_bytes = size_t(header_.width) * (rgba ? 4 : 1) * bytes_per_sample;
    std::vector<png_bytep> rows(size_t(header_.height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = pixels + y * row_bytes;
    bool layout_ok = false;
    if (!readRows(png_, info_, &raw_, rgba, rows.data(), row_bytes, &layout_ok)) fail();
    if (!layout_ok)
      throw Error("cannot decode " + what_ + " " + name_ + ": unexpected PNG layout (colour type " +
                  std::to_string(raw_.color_type) + ", " + std::to_string(raw_.bit_depth) + " bits)");
    return (raw_.color_type & PNG_COLOR_MASK_ALPHA) != 0 || (raw_.color_type == PNG_COLOR_TYPE_PALETTE && raw_.has_trns);
  }

  [[noreturn]] void fail() const {
    const std::string why = error_.text[0] ? error_.text : "not a valid PNG";
    throw Error("cannot decode " + what_ + " " + name_ + ": " + why);
  }

  std::string name_, what_;
  PngState state_;
  PngError error_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  PngRaw raw_;
  ImageHeader header_;
};

// ---- JPEG --------------------------------------------------------------------------------------

struct JpegErrors {
  jpeg_error_mgr mgr;  // first: libjpeg hands back a pointer to it
  std::jmp_buf jump;
  char error[JMSG_LENGTH_MAX] = {0};
  bool truncated = false;
};

void jpegOnError(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->error);
  std::longjmp(e->jump, 1);
}

// libjpeg only warns when data is missing (it fills the rest of the image with grey): a frame
// with a grey end is a silent wrong result, so these warnings make the file an error.
void jpegOnMessage(j_common_ptr cinfo, int level) {
  if (level >= 0) return;  // trace messages
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  ++cinfo->err->num_warnings;
  const int code = cinfo->err->msg_code;
  if ((code == JWRN_JPEG_EOF || code == JWRN_HIT_MARKER || code == JWRN_MUST_RESYNC) && !e->truncated) {
    e->truncated = true;
    (*cinfo->err->format_message)(cinfo, e->error);
  }
}

struct JpegRaw {
  JDIMENSION width = 0, height = 0;
  int components = 0;
};

class JpegReader {
 public:
  JpegReader(const uint8_t* data, size_t size, std::string name, std::string what)
      : name_(std::move(name)), what_(std::move(what)) {
    cinfo_.err = jpeg_std_error(&errors_.mgr);
    errors_.mgr.error_exit = jpegOnError;
    errors_.mgr.emit_message = jpegOnMessage;
    if (!create(&cinfo_, &errors_, data, size)) fail();
    created_ = true;
  }
  ~JpegReader() {
    if (created_) jpeg_destroy_decompress(&cinfo_);
  }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  ImageHeader readHeader() {
    if (!header(&cinfo_, &errors_, &raw_)) fail();
    checkPixelCount(raw_.width, raw_.height, name_, what_);
    ImageHeader h;
    h.width = int(raw_.width);
    h.height = int(raw_.height);
    h.channels = raw_.components > 1 ? 3 : 1;  // OpenCV: colour (CMYK too) is 3 channels
    h.bits = 8;
    return h;
  }

  // RGBA rows (4 bytes a pixel, a = 255), CMYK converted as OpenCV converts it.
  void readRgba(Rgb8* pixels) {
    const bool cmyk = raw_.components == 4;
    std::vector<JSAMPROW> rows(raw_.height);
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = reinterpret_cast<JSAMPROW>(pixels + y * raw_.width);
    bool layout_ok = false;
    if (!decode(&cinfo_, &errors_, cmyk, rows.data(), &layout_ok)) fail();
    if (!layout_ok) throw Error("cannot decode " + what_ + " " + name_ + ": unexpected JPEG output layout");
    if (errors_.truncated)
      throw Error("cannot decode " + what_ + " " + name_ + ": truncated or corrupt JPEG (" + errors_.error + ")");
    if (cmyk) {
      for (size_t i = 0; i < size_t(raw_.width) * raw_.height; ++i) {
        Rgb8& p = pixels[i];
        const int c = p.r, m = p.g, y = p.b, k = p.a;  // Adobe CMYK, as libjpeg delivers it
        p = {uint8_t(k - ((255 - c) * k >> 8)), uint8_t(k - ((255 - m) * k >> 8)), uint8_t(k - ((255 - y) * k >> 8)), 255};
      }
    }
  }

 private:
  static bool create(jpeg_decompress_struct* cinfo, JpegErrors* errors, const uint8_t* data, size_t size) {
    if (setjmp(errors->jump)) return false;
    jpeg_create_decompress(cinfo);
    jpeg_mem_src(cinfo, data, static_cast<unsigned long>(size));
    return true;
  }
  static bool header(jpeg_decompress_struct* cinfo, JpegErrors* errors, JpegRaw* raw) {
    if (setjmp(errors->jump)) return false;
    jpeg_read_header(cinfo, TRUE);
    raw->width = cinfo->image_width;
    raw->height = cinfo->image_height;
    raw->components = cinfo->num_components;
    return true;
  }
  static bool decode(jpeg_decompress_struct* cinfo, JpegErrors* errors, bool cmyk, JSAMPROW* rows, bool* layout_ok) {
    if (setjmp(errors->jump)) return false;
    cinfo->out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
    const JDIMENSION width = cinfo->image_width, height = cinfo->image_height;
    jpeg_start_decompress(cinfo);
    *layout_ok = cinfo->output_width == width && cinfo->output_height == height && cinfo->output_components == 4;
    if (!*layout_ok) {
      jpeg_abort_decompress(cinfo);
      return true;
    }
    while (cinfo->output_scanline < cinfo->output_height)
      jpeg_read_scanlines(cinfo, rows + cinfo->output_scanline, cinfo->output_height - cinfo->output_scanline);
    jpeg_finish_decompress(cinfo);
    return true;
  }

  [[noreturn]] void fail() const {
    throw Error("cannot decode " + what_ + " " + name_ + ": " + (errors_.error[0] ? errors_.error : "not a valid JPEG"));
  }

  std::string name_, what_;
  jpeg_decompress_struct cinfo_{};
  JpegErrors errors_;
  JpegRaw raw_;
  bool created_ = false;
};

[[noreturn]] void notAnImage(const std::string& name, const std::string& what, size_t size) {
  throw Error("cannot decode " + what + " " + name + ": " +
              (size == 0 ? std::string("the file is empty") : std::string("not a PNG or JPEG file")));
}

// round(v / 257), as OpenCV's convertTo(CV_8U, 1 / 257.) (v / 257 is never a tie).
uint8_t to8(uint16_t v) { return uint8_t((uint32_t(v) * 2 + 257) / 514); }

// ---- PNG writing -------------------------------------------------------------------------------

struct PngOut {
  std::string bytes;
};

void pngWriteBytes(png_structp png, png_bytep data, size_t n) {
  auto* out = static_cast<PngOut*>(png_get_io_ptr(png));
  try {
    out->bytes.append(reinterpret_cast<const char*>(data), n);
  } catch (...) {
    png_error(png, "out of memory");
  }
}
void pngFlush(png_structp) {}

bool writePng(png_structp png, png_infop info, int width, int height, int channels, int bits, bool compact,
              png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bits,
               channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  if (compact) {
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_ALL_FILTERS);
    png_set_compression_level(png, Z_DEFAULT_COMPRESSION);
  } else {
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_compression_strategy(png, Z_RLE);
  }
  png_write_info(png, info);
  if (bits == 16) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

struct JpegOut {
  unsigned char* bytes = nullptr;  // malloc'ed by jpeg_mem_dest
  unsigned long size = 0;
};

bool writeJpeg(jpeg_compress_struct* cinfo, JpegErrors* errors, const ColorImage* color, int quality, JpegOut* out) {
  if (setjmp(errors->jump)) return false;
  jpeg_create_compress(cinfo);
  jpeg_mem_dest(cinfo, &out->bytes, &out->size);
  cinfo->image_width = JDIMENSION(color->width());
  cinfo->image_height = JDIMENSION(color->height());
  cinfo->input_components = 4;
  cinfo->in_color_space = JCS_EXT_RGBX;  // Rgb8 is r, g, b, a in memory
  jpeg_set_defaults(cinfo);
  jpeg_set_quality(cinfo, quality, TRUE);
  cinfo->optimize_coding = TRUE;
  jpeg_start_compress(cinfo, TRUE);
  while (cinfo->next_scanline < cinfo->image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(
        reinterpret_cast<const JSAMPLE*>(color->data() + size_t(cinfo->next_scanline) * color->width()));
    jpeg_write_scanlines(cinfo, &row, 1);
  }
  jpeg_finish_compress(cinfo);
  return true;
}

}  // namespace

std::string ImageHeader::describe() const {
  return std::to_string(bits) + "-bit " + std::to_string(channels) + "-channel";
}

std::vector<uint8_t> readFileBytes(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    if (std::filesystem::exists(path, ec)) throw Error(what + " " + path + " is not a file");
    throw Error(what + " not found: " + path);
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("cannot open " + what + " " + path);
  std::vector<uint8_t> bytes(static_cast<size_t>(std::filesystem::file_size(path, ec)));
  const size_t n = ec ? 0 : std::fread(bytes.data(), 1, bytes.size(), f);
  const bool failed = ec || n != bytes.size() || std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw Error("cannot read " + what + " " + path);
  return bytes;
}

ImageHeader decodeImageHeader(const uint8_t* data, size_t size, const std::string& name) {
  if (isPng(data, size)) return PngReader(data, size, name, "image").readHeader();
  if (isJpeg(data, size)) return JpegReader(data, size, name, "image").readHeader();
  notAnImage(name, "image", size);
}

ImageHeader decodeExrHeader(const uint8_t* data, size_t size, const std::string& name, const std::string& what) {
  // OpenEXR: magic, version, then attributes "name\0type\0" int32 size, value; an empty name ends them.
  const auto u32 = [&](size_t at) {
    return uint32_t(data[at]) | uint32_t(data[at + 1]) << 8 | uint32_t(data[at + 2]) << 16 | uint32_t(data[at + 3]) << 24;
  };
  const auto bad = [&](const std::string& why) -> Error {
    return Error("cannot decode " + what + " " + name + ": " + why);
  };
  if (size < 8 || u32(0) != 20000630u) throw bad(size == 0 ? "the file is empty" : "not an OpenEXR file");
  size_t at = 8;
  const auto cString = [&]() {
    const void* end = at < size ? std::memchr(data + at, 0, size - at) : nullptr;
    if (!end) throw bad("the header ends early (truncated)");
    std::string s(reinterpret_cast<const char*>(data + at), static_cast<const uint8_t*>(end) - (data + at));
    at += s.size() + 1;
    return s;
  };
  for (;;) {
    const std::string attribute = cString();
    if (attribute.empty()) break;
    const std::string type = cString();
    if (at + 4 > size) throw bad("the header ends early (truncated)");
    const uint32_t bytes = u32(at);
    at += 4;
    if (bytes > size - at) throw bad("the header ends early (truncated)");
    if (attribute == "dataWindow" && type == "box2i" && bytes == 16) {
      const int64_t x0 = int32_t(u32(at)), y0 = int32_t(u32(at + 4)), x1 = int32_t(u32(at + 8)), y1 = int32_t(u32(at + 12));
      const int64_t w = x1 - x0 + 1, h = y1 - y0 + 1;
      checkPixelCount(uint64_t(std::max<int64_t>(w, 0)), uint64_t(std::max<int64_t>(h, 0)), name, what);
      ImageHeader header;
      header.width = int(w);
      header.height = int(h);
      return header;
    }
    at += bytes;
  }
  throw bad("the header has no dataWindow");
}

DepthImage decodeDepthPng(const uint8_t* data, size_t size, const std::string& name, float units_per_metre,
                          const std::string& what) {
  if (!(units_per_metre > 0)) throw Error("depth scale must be positive, got " + std::to_string(units_per_metre));
  if (isJpeg(data, size))
    throw Error(what + " " + name + " is a JPEG; depth must be a 16-bit single-channel PNG (value / " +
                std::to_string(int(units_per_metre)) + " = metres)");
  if (!isPng(data, size)) notAnImage(name, what, size);
  const float inv = 1.f / units_per_metre;
  png_inflate::Rows rows;
  if (png_inflate::decode(data, size, png_inflate::Layout::Grey16, kMaxImagePixels, rows)) {
    DepthImage depth = DepthImage::forOverwrite(rows.width, rows.height);
    for (int y = 0; y < rows.height; ++y) {
      const uint8_t* in = rows.row(y);
      float* out = depth.data() + size_t(y) * rows.width;
      for (int x = 0; x < rows.width; ++x) out[x] = float(uint16_t(in[2 * x] << 8 | in[2 * x + 1])) * inv;
    }
    return depth;
  }
  PngReader png(data, size, name, what);
  const ImageHeader h = png.readHeader();
  if (h.channels != 1 || h.bits != 16)
    throw Error(what + " " + name + " is " + h.describe() + "; depth must be a 16-bit single-channel PNG (value / " +
                std::to_string(int(units_per_metre)) + " = metres)");
  std::vector<uint16_t> raw(size_t(h.width) * h.height);
  png.readGrey(reinterpret_cast<uint8_t*>(raw.data()));
  DepthImage depth = DepthImage::forOverwrite(h.width, h.height);
  float* out = depth.data();
  for (size_t i = 0; i < raw.size(); ++i) out[i] = float(raw[i]) * inv;
  return depth;
}

ColorImage decodeColorImage(const uint8_t* data, size_t size, const std::string& name, const std::string& what) {
  if (isJpeg(data, size)) {
    JpegReader jpeg(data, size, name, what);
    const ImageHeader h = jpeg.readHeader();
    ColorImage color(h.width, h.height);
    jpeg.readRgba(color.data());
    return color;
  }
  if (!isPng(data, size)) notAnImage(name, what, size);
  png_inflate::Rows rows;
  const bool rgb = png_inflate::decode(data, size, png_inflate::Layout::Rgb8, kMaxImagePixels, rows);
  if (rgb || png_inflate::decode(data, size, png_inflate::Layout::Rgba8, kMaxImagePixels, rows)) {
    ColorImage color = ColorImage::forOverwrite(rows.width, rows.height);
    const int step = rgb ? 3 : 4;
    for (int y = 0; y < rows.height; ++y) {
      const uint8_t* in = rows.row(y);
      Rgb8* out = color.data() + size_t(y) * rows.width;
      for (int x = 0; x < rows.width; ++x, in += step) out[x] = {in[0], in[1], in[2], 255};
    }
    return color;
  }
  PngReader png(data, size, name, what);
  const ImageHeader h = png.readHeader();
  ColorImage color(h.width, h.height);
  const size_t n = size_t(h.width) * h.height;
  if (h.bits == 16) {
    std::vector<uint16_t> wide(n * 4);
    png.readRgba(reinterpret_cast<uint8_t*>(wide.data()));
    Rgb8* out = color.data();
    for (size_t i = 0; i < n; ++i) out[i] = {to8(wide[4 * i]), to8(wide[4 * i + 1]), to8(wide[4 * i + 2]), 255};
    return color;
  }
  if (png.readRgba(reinterpret_cast<uint8_t*>(color.data()))) {
    Rgb8* out = color.data();
    for (size_t i = 0; i < n; ++i) out[i].a = 255;
  }
  return color;
}

Image<uint16_t> decodeGreyPng(const uint8_t* data, size_t size, const std::string& name, ImageHeader& header,
                              const std::string& what) {
  if (isJpeg(data, size)) {
    header = JpegReader(data, size, name, what).readHeader();
    header.channels = 0;  // a JPEG is never taken for class ids (lossy)
    return {};
  }
  if (!isPng(data, size)) notAnImage(name, what, size);
  png_inflate::Rows rows;
  const bool wide = png_inflate::decode(data, size, png_inflate::Layout::Grey16, kMaxImagePixels, rows);
  if (wide || png_inflate::decode(data, size, png_inflate::Layout::Grey8, kMaxImagePixels, rows)) {
    header.width = rows.width;
    header.height = rows.height;
    header.channels = 1;
    header.bits = wide ? 16 : 8;
    Image<uint16_t> out(rows.width, rows.height);
    for (int y = 0; y < rows.height; ++y) {
      const uint8_t* in = rows.row(y);
      uint16_t* line = out.data() + size_t(y) * rows.width;
      for (int x = 0; x < rows.width; ++x) line[x] = wide ? uint16_t(in[2 * x] << 8 | in[2 * x + 1]) : in[x];
    }
    return out;
  }
  PngReader png(data, size, name, what);
  header = png.readHeader();
  if (header.channels != 1) return {};
  Image<uint16_t> out(header.width, header.height);
  if (header.bits == 16) {
    png.readGrey(reinterpret_cast<uint8_t*>(out.data()));
  } else {
    std::vector<uint8_t> narrow(size_t(header.width) * header.height);
    png.readGrey(narrow.data());
    for (size_t i = 0; i < narrow.size(); ++i) out.data()[i] = narrow[i];
  }
  return out;
}

std::string encodePng(const void* pixels, int width, int height, int channels, int bits, const std::string& name,
                      PngCompression compression) {
  if (width <= 0 || height <= 0) throw Error("cannot write an empty image to " + name);
  if ((channels != 1 && channels != 3) || (bits != 8 && bits != 16))
    throw Error("cannot encode " + name + ": PNG writing takes 1 or 3 channels of 8 or 16 bits");
  const size_t row_bytes = size_t(width) * channels * (bits / 8);
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (size_t y = 0; y < rows.size(); ++y)
    rows[y] = const_cast<png_bytep>(static_cast<const uint8_t*>(pixels) + y * row_bytes);
  PngOut out;
  PngError error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, pngOnError, pngOnWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  bool ok = false;
  if (png && info) {
    png_set_write_fn(png, &out, pngWriteBytes, pngFlush);
    ok = writePng(png, info, width, height, channels, bits, compression == PngCompression::Compact, rows.data());
  }
  png_destroy_write_struct(&png, &info);
  if (!ok) throw Error("cannot encode PNG for " + name + (error.text[0] ? std::string(": ") + error.text : ""));
  return std::move(out.bytes);
}

std::string encodeJpeg(const ColorImage& color, int quality, const std::string& name) {
  if (color.empty()) throw Error("cannot write an empty image to " + name);
  if (quality < 1 || quality > 100) throw Error("JPEG quality must be 1..100, got " + std::to_string(quality));
  jpeg_compress_struct cinfo{};
  JpegErrors errors;
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = jpegOnError;
  JpegOut out;
  const bool ok = writeJpeg(&cinfo, &errors, &color, quality, &out);
  jpeg_destroy_compress(&cinfo);
  std::string bytes = ok ? std::string(reinterpret_cast<const char*>(out.bytes), out.size) : std::string();
  std::free(out.bytes);
  if (!ok) throw Error("cannot encode JPEG for " + name + ": " + errors.error);
  return bytes;
}

}  // namespace vf
