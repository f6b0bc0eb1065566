#include "viewer/display_check.h"

#include <X11/Xlib.h>

#include <cstdlib>
#include <string>

#include "core/error.h"

namespace vf::viewer {

void requireDisplay(bool offscreen) {
  const char* env = std::getenv("DISPLAY");
  const std::string display = env ? env : "";
  if (Display* d = XOpenDisplay(nullptr)) {
    XCloseDisplay(d);
    return;
  }
  const std::string what = display.empty() ? "DISPLAY is not set" : "cannot open X display '" + display + "'";
  if (offscreen)
    throw Error(what + ": this VTK renders through X (GLX) even offscreen; run under a virtual X server, e.g. "
                       "`xvfb-run -a vdbfuse-view scene.vdb --screenshot out.png`");
  throw Error(what + ": the interactive viewer needs a display (ssh -X, or a desktop session); for pictures "
                     "without one use --screenshot out.png under `xvfb-run -a`");
}

}  // namespace vf::viewer
