#pragma once
// Debian's VTK renders through GLX, so even offscreen rendering needs an X server; without one
// VTK aborts the process. This check turns that into a vf::Error that says what to do.
namespace vf::viewer {

// Throws vf::Error (naming $DISPLAY and suggesting xvfb-run) when no X display can be opened.
void requireDisplay(bool offscreen);

}  // namespace vf::viewer
