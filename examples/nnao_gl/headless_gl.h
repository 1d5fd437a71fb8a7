#pragma once
// An OpenGL 3.3 core context with no window and no display server: EGL's surfaceless
// platform (EGL_MESA_platform_surfaceless), which Mesa serves with llvmpipe on a
// machine without a GPU. Rendering goes to framebuffer objects; nothing is shown.
// Every failure throws, naming the step and the EGL error, so a test that needs a
// context fails with the reason instead of skipping.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace nns::gl {

class HeadlessGl {
 public:
  HeadlessGl() {
    // Client extensions: which platforms this libEGL (glvnd + its vendors) can open.
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!ext || !std::strstr(ext, "EGL_MESA_platform_surfaceless"))
      fail(
          "EGL offers no surfaceless platform (EGL_MESA_platform_surfaceless); is Mesa's EGL installed "
          "(Debian libegl-mesa0, libgl1-mesa-dri)?");
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) fail("eglGetPlatformDisplayEXT is missing");
    display_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, &major, &minor))
      fail("cannot initialise the surfaceless EGL display (no Mesa driver: Debian libgl1-mesa-dri)");
    if (!eglBindAPI(EGL_OPENGL_API)) fail("EGL cannot bind desktop OpenGL");
    const EGLint attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    // No config and no surface (EGL_KHR_no_config_context, EGL_KHR_surfaceless_context):
    // every pass draws into its own framebuffer object.
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) fail("cannot create an OpenGL 3.3 core context");
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) fail("cannot make the context current");
  }
  // The display is left initialised: eglTerminate would unload Mesa's driver, whose few
  // bytes of process-lifetime state LeakSanitizer then reports from an unknown module
  // (and no suppression can name); the process ends soon after anyway.
  ~HeadlessGl() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  }
  HeadlessGl(const HeadlessGl&) = delete;
  HeadlessGl& operator=(const HeadlessGl&) = delete;

  // "llvmpipe (LLVM 15.0.6, 256 bits)": which driver ran the shaders.
  std::string renderer() const { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }

 private:
  [[noreturn]] void fail(const std::string& what) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(eglGetError()));
    if (display_ != EGL_NO_DISPLAY) eglTerminate(display_);
    throw std::runtime_error("headless OpenGL: " + what + " (EGL error " + code + ")");
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace nns::gl
