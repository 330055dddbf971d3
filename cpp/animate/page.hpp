// The animation page: one self-contained HTML file (every script and style inline, the frames as
// data, a Content-Security-Policy of default-src 'none' so the page cannot load anything).
#pragma once

#include <string>

#include "animate/scene.hpp"

namespace pcsim::animate {

/// The page for a scene: a canvas (2-D, or 3-D with an orbiting camera), a time slider, play
/// and pause, speed, the displacement magnification about the moving mean (shown on screen),
/// force arrows with their scale, contact modes and events on the timeline. The fragment
/// `#t=1.25&mag=1` opens it paused at that time; the page writes what it draws (every named
/// point's drawn coordinates and pixels) into <pre id="pcsim-state"> and window.pcsimState().
std::string animation_html(const Scene& scene);

}  // namespace pcsim::animate
