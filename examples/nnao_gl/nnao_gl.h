#pragma once
// The engine side of NNAO: export-nnao's passes (nnao.frag, nnao_blur.frag, a grid
// model's nnao_filters.exr, a low-resolution model's nnao_downsample.frag and
// nnao_upsample.frag) bound to G-buffer textures and drawn, as docs/nnao.md
// ("The shader in an engine") describes. Needs a current OpenGL 3.3 core context
// (headless_gl.h gives one without a display).
//
// Textures are laid out as an OpenGL renderer's targets are: row 0 at the bottom, so
// the CPU planes (row 0 at the top, the dataset's order) are flipped on upload and on
// read-back. The filter atlas is a table, not an image: uploaded as stored.
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "screen_space/gbuffer.h"

namespace nns::gl {

class NnaoGlPasses {
 public:
  // Compiles the folder's shaders; a grid model's nnao.frag also needs nnao_filters.exr.
  explicit NnaoGlPasses(const std::string& export_dir) {
    namespace fs = std::filesystem;
    glGenVertexArrays(1, &vao_);  // the core profile draws only with a vertex array bound
    glGenFramebuffers(1, &fbo_);
    const std::string ao_file = (fs::path(export_dir) / "nnao.frag").string();
    ao_program_ = program(ao_file);
    const std::string blur_file = (fs::path(export_dir) / "nnao_blur.frag").string();
    blur_program_ = program(blur_file);
    blur_pairs_ = blur_pairs(blur_file);
    // A model at 1/s resolution (export-nnao writes both files, or neither).
    const std::string down_file = (fs::path(export_dir) / "nnao_downsample.frag").string();
    if (fs::exists(down_file)) {
      const std::string up_file = (fs::path(export_dir) / "nnao_upsample.frag").string();
      if (!fs::exists(up_file)) throw std::runtime_error(down_file + " needs " + up_file + ", which is missing");
      down_program_ = program(down_file);
      up_program_ = program(up_file);
      scale_ = define_int(down_file, "NNAO_DOWNSAMPLE", 1, 1, 8);
    }
    if (glGetUniformLocation(ao_program_, "uFilters") >= 0) {
      const std::string atlas = (fs::path(export_dir) / "nnao_filters.exr").string();
      if (!fs::exists(atlas)) throw std::runtime_error(ao_file + " samples filters, but " + atlas + " is missing");
      const data::View f = data::read_view(atlas);
      std::vector<float> rgba(size_t(f.width) * f.height * 4);
      const char* names[4] = {"R", "G", "B", "A"};
      for (int c = 0; c < 4; ++c)
        for (size_t i = 0; i < size_t(f.width) * f.height; ++i) rgba[i * 4 + c] = f.channel(names[c])[i];
      filters_ = texture(GL_RGBA32F, f.width, f.height, GL_RGBA, rgba.data());
    }
  }
  ~NnaoGlPasses() {
    const GLuint textures[] = {filters_, depth_, normal_, ao_, tmp_, out_, low_depth_, low_normal_, low_out_};
    glDeleteTextures(9, textures);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteVertexArrays(1, &vao_);
    for (GLuint p : {ao_program_, blur_program_, down_program_, up_program_})
      if (p) glDeleteProgram(p);
  }
  NnaoGlPasses(const NnaoGlPasses&) = delete;
  NnaoGlPasses& operator=(const NnaoGlPasses&) = delete;

  // The G-buffer's planes as R32F depth and RGB32F normals; its camera and radius
  // become the passes' uniforms.
  void set_gbuffer(const screen_space::GBuffer& g) {
    g_ = g;
    std::vector<float> normals(size_t(g.pixels()) * 3);
    for (int64_t i = 0; i < g.pixels(); ++i)
      normals[size_t(i) * 3] = g.nx[i], normals[size_t(i) * 3 + 1] = g.ny[i], normals[size_t(i) * 3 + 2] = g.nz[i];
    const GLuint old[] = {depth_, normal_, ao_, tmp_, out_, low_depth_, low_normal_, low_out_};
    glDeleteTextures(8, old);
    depth_ = texture(GL_R32F, g.width, g.height, GL_RED, flip_rows(g.z, 1).data());
    normal_ = texture(GL_RGB32F, g.width, g.height, GL_RGB, flip_rows(normals.data(), 3).data());
    // The NNAO pass and the blur draw at the working size: the frame's, or 1/s of it.
    work_w_ = (g.width + scale_ - 1) / scale_, work_h_ = (g.height + scale_ - 1) / scale_;
    ao_ = texture(GL_R32F, work_w_, work_h_, GL_RED, nullptr);
    tmp_ = texture(GL_R32F, work_w_, work_h_, GL_RED, nullptr);
    out_ = texture(GL_R32F, g.width, g.height, GL_RED, nullptr);
    low_depth_ = low_normal_ = low_out_ = 0;
    if (scale_ > 1) {
      low_depth_ = texture(GL_R32F, work_w_, work_h_, GL_RED, nullptr);
      low_normal_ = texture(GL_RGBA32F, work_w_, work_h_, GL_RGBA, nullptr);
      low_out_ = texture(GL_R32F, work_w_, work_h_, GL_RED, nullptr);
    }
  }

  struct Frame {
    int samples = 64;    // uSamples (grid models)
    uint32_t index = 0;  // uFrame: the jitter pattern's seed (grid models)
  };

  // Every pass on the GPU, read back once: nnao-infer's image.
  std::vector<float> run(const Frame& f) {
    if (scale_ > 1) draw_downsample();
    draw_ao(f);
    draw_blur();
    if (scale_ > 1) draw_upsample();
    return read(out_, g_.width, g_.height);
  }
  // The NNAO pass alone: the image before the blur (at the working size).
  std::vector<float> ao_pass(const Frame& f) {
    if (scale_ > 1) draw_downsample();
    draw_ao(f);
    return read(ao_, work_w_, work_h_);
  }
  // The blur alone, on an image given top row first (full-resolution models).
  std::vector<float> blur(const std::vector<float>& image) {
    if (scale_ > 1)
      throw std::logic_error("NnaoGlPasses::blur: a model at 1/s resolution blurs its low frame inside run()");
    glBindTexture(GL_TEXTURE_2D, ao_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g_.width, g_.height, GL_RED, GL_FLOAT,
                    flip_rows(image.data(), 1, g_.width, g_.height).data());
    draw_blur();
    return read(out_, g_.width, g_.height);
  }
  int downsample() const { return scale_; }

 private:
  // The G-buffer planes the NNAO pass and the blur read: the frame's, or 1/s of them.
  GLuint work_depth() const { return scale_ > 1 ? low_depth_ : depth_; }
  GLuint work_normal() const { return scale_ > 1 ? low_normal_ : normal_; }
  // The blur's last target: out_ at full resolution; low_out_ before the upsample.
  GLuint blur_out() const { return scale_ > 1 ? low_out_ : out_; }

  void draw_downsample() {
    glUseProgram(down_program_);
    bind(down_program_, "uDepth", 0, depth_);
    bind(down_program_, "uNormal", 1, normal_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, low_depth_, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, low_normal_, 0);
    const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
    draw(work_w_, work_h_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
    const GLenum one[] = {GL_COLOR_ATTACHMENT0};
    glDrawBuffers(1, one);
  }
  void draw_upsample() {
    glUseProgram(up_program_);
    bind_gbuffer(up_program_, depth_, normal_);
    bind(up_program_, "uAO", 2, low_out_);
    bind(up_program_, "uLowDepth", 3, low_depth_);
    bind(up_program_, "uLowNormal", 4, low_normal_);
    draw_into(out_, g_.width, g_.height);
  }
  void draw_ao(const Frame& f) {
    glUseProgram(ao_program_);
    bind_gbuffer(ao_program_, work_depth(), work_normal());
    if (filters_) bind(ao_program_, "uFilters", 2, filters_);
    set_int(ao_program_, "uSamples", f.samples);
    if (GLint u = glGetUniformLocation(ao_program_, "uFrame"); u >= 0) glUniform1ui(u, f.index);
    draw_into(ao_, work_w_, work_h_);
  }
  // Horizontal into tmp_, then vertical into the blur's target, as the CPU's separable
  // blur; the pair blur_pairs_ times, each after the first on the last one's result.
  void draw_blur() {
    glUseProgram(blur_program_);
    bind_gbuffer(blur_program_, work_depth(), work_normal());
    const GLint step = glGetUniformLocation(blur_program_, "uStep");
    for (int pair = 0; pair < blur_pairs_; ++pair) {
      bind(blur_program_, "uAO", 2, pair == 0 ? ao_ : blur_out());
      glUniform2i(step, 1, 0);
      draw_into(tmp_, work_w_, work_h_);
      bind(blur_program_, "uAO", 2, tmp_);
      glUniform2i(step, 0, 1);
      draw_into(blur_out(), work_w_, work_h_);
    }
  }
  // The shader's "#define NNAO_BLUR_PAIRS N" (export-nnao writes it; 1 without it).
  static int blur_pairs(const std::string& frag_file) { return define_int(frag_file, "NNAO_BLUR_PAIRS", 1, 1, 16); }
  // A shader's "#define NAME N" (export-nnao writes it), range-checked; `absent` without it.
  static int define_int(const std::string& frag_file, const std::string& name, int absent, int lo, int hi) {
    std::ifstream in(frag_file);
    const std::string key = "#define " + name + " ";
    for (std::string line; std::getline(in, line);)
      if (line.rfind(key, 0) == 0) {
        const int n = std::atoi(line.c_str() + key.size());
        if (n < lo || n > hi)
          throw std::runtime_error(frag_file + ": " + name + " must be " + std::to_string(lo) + ".." +
                                   std::to_string(hi) + ", not '" + line.substr(key.size()) + "'");
        return n;
      }
    return absent;
  }
  void bind_gbuffer(GLuint prog, GLuint depth, GLuint normal) {
    bind(prog, "uDepth", 0, depth);
    bind(prog, "uNormal", 1, normal);
    glUniform2f(glGetUniformLocation(prog, "uTanHalfFov"), g_.sx, g_.sy);
    glUniform1f(glGetUniformLocation(prog, "uRadius"), g_.radius);
  }
  void draw_into(GLuint target, int w, int h) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    draw(w, h);
  }
  void draw(int w, int h) {
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("OpenGL: a float render target is incomplete");
    glViewport(0, 0, w, h);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
      throw std::runtime_error("OpenGL error " + std::to_string(e) + " in a pass");
  }
  std::vector<float> read(GLuint source, int w, int h) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, source, 0);
    std::vector<float> rows(size_t(w) * size_t(h));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, rows.data());
    return flip_rows(rows.data(), 1, w, h);
  }

  static void bind(GLuint prog, const char* sampler, int unit, GLuint tex) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, tex);
    glUniform1i(glGetUniformLocation(prog, sampler), unit);
  }
  static void set_int(GLuint prog, const char* name, int v) {
    if (GLint u = glGetUniformLocation(prog, name); u >= 0) glUniform1i(u, v);
  }
  // texelFetch only: no filtering, no mipmaps (with the default minification filter a
  // texture without mipmaps is incomplete and reads as 0).
  static GLuint texture(GLenum internal, int w, int h, GLenum format, const float* data) {
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, GL_FLOAT, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  }
  std::vector<float> flip_rows(const float* p, int channels) const {
    return flip_rows(p, channels, g_.width, g_.height);
  }
  static std::vector<float> flip_rows(const float* p, int channels, int w, int h) {
    const size_t row = size_t(w) * channels;
    std::vector<float> out(row * h);
    for (int y = 0; y < h; ++y)
      std::copy(p + row * y, p + row * (y + 1), out.begin() + std::ptrdiff_t(row * (h - 1 - y)));
    return out;
  }
  static GLuint shader(GLenum kind, const std::string& source, const std::string& name) {
    GLuint s = glCreateShader(kind);
    const char* text = source.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    check(s, false, name + ": does not compile: ");
    return s;
  }
  // Throws with the driver's log when a shader did not compile or a program did not link.
  static void check(GLuint id, bool is_program, const std::string& what) {
    GLint ok = 0;
    char log[4096] = {};
    if (is_program) glGetProgramiv(id, GL_LINK_STATUS, &ok);
    else glGetShaderiv(id, GL_COMPILE_STATUS, &ok);
    if (ok) return;
    if (is_program) glGetProgramInfoLog(id, sizeof log, nullptr, log), glDeleteProgram(id);
    else glGetShaderInfoLog(id, sizeof log, nullptr, log), glDeleteShader(id);
    throw std::runtime_error(what + log);
  }
  // A full-screen triangle: the vertex stage every pass shares.
  static GLuint program(const std::string& frag_file) {
    std::ifstream in(frag_file);
    if (!in) throw std::runtime_error("cannot read " + frag_file);
    std::stringstream text;
    text << in.rdbuf();
    const GLuint vs = shader(GL_VERTEX_SHADER,
                             "#version 330 core\nvoid main() {\n"
                             "  vec2 c = vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0;\n"
                             "  gl_Position = vec4(c, 0.0, 1.0);\n}\n",
                             "the full-screen vertex shader");
    const GLuint fs = shader(GL_FRAGMENT_SHADER, text.str(), frag_file);
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    check(p, true, frag_file + ": does not link: ");
    return p;
  }

  screen_space::GBuffer g_;
  GLuint vao_ = 0, fbo_ = 0, ao_program_ = 0, blur_program_ = 0, down_program_ = 0, up_program_ = 0;
  int blur_pairs_ = 1, scale_ = 1, work_w_ = 0, work_h_ = 0;
  GLuint filters_ = 0, depth_ = 0, normal_ = 0, ao_ = 0, tmp_ = 0, out_ = 0;
  GLuint low_depth_ = 0, low_normal_ = 0, low_out_ = 0;  // a model at 1/s resolution
};

}  // namespace nns::gl
