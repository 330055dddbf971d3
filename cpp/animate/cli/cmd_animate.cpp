// `pcsim animate DIR [--video FILE.mp4|FILE.gif]`: the run in DIR drawn by its model's
// [model.draw] table, as one self-contained page DIR/animation.html (and a video).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "animate/page.hpp"
#include "animate/scene.hpp"
#include "animate/video.hpp"
#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"

namespace {

namespace fs = std::filesystem;

struct AnimateArgs {
  std::string dir;
  std::string video;
  int frames = 2000;
  double magnify = 0;
  int fps = 25;
  double speed = 1;
};

// The video's path: a new file (its directory must exist), or pcsim's own animation.mp4/.gif
// in the run directory; never a file pcsim did not write, a link or a directory.
void check_video_path(const fs::path& file, const fs::path& run_dir) {
  const std::string f = file.string();
  const std::string ext = file.extension().string();
  if (ext != ".mp4" && ext != ".gif")
    throw pcsim::InputError("--video " + f + ": expected a file name ending in .mp4 or .gif");
  if (file.filename().string().size() > pcsim::kMaxOutputLeafBytes)
    throw pcsim::InputError("--video " + f + ": expected a file name of at most " +
                            std::to_string(pcsim::kMaxOutputLeafBytes) + " bytes");
  const fs::path parent = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw pcsim::InputError("--video " + f + ": the directory " + parent.string() +
                            " does not exist (pcsim writes the file you name, and nothing else)");
  const bool in_run = fs::equivalent(parent, run_dir, ec);
  const bool own_name = file.filename() == "animation.mp4" || file.filename() == "animation.gif";
  if (in_run && !own_name)
    throw pcsim::InputError("--video " + f + ": in a run directory pcsim writes only animation.mp4 "
                            "or animation.gif (a run replaces its directory whole); name one of "
                            "those or a file elsewhere");
  const auto st = fs::symlink_status(file, ec);
  if (!fs::exists(st)) return;
  const bool own = fs::is_regular_file(st) && own_name && in_run;
  if (!own)
    throw pcsim::InputError("--video " + f + ": the file exists and pcsim did not write it (pcsim "
                            "replaces only its own DIR/animation.mp4 or DIR/animation.gif); "
                            "remove it or name a new file");
}

void animate(const AnimateArgs& a) {
  const fs::path dir(a.dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw pcsim::InputError(a.dir + ": not a directory; expected the output directory of `pcsim "
                                    "run` or `pcsim steady`");
  const std::string owner = pcsim::directory_owner(dir);
  if (owner != "run" && owner != "steady" && owner != "modes")
    throw pcsim::InputError(a.dir + ": not the output directory of `pcsim run`, `pcsim steady` or `pcsim modes` (" +
                            (owner.empty() ? std::string("it has no ") + pcsim::kOwnerMarker + " marker"
                                           : "it is pcsim " + owner + "'s") + ")");
  if (!(a.frames >= 2 && a.frames <= 100000))
    throw pcsim::InputError("--frames: expected a number of frames in [2, 100000], got " + std::to_string(a.frames));
  if (a.magnify != 0 && !(a.magnify >= 1 && a.magnify <= 1e9))
    throw pcsim::InputError("--magnify: expected a number in [1, 1e9], got " + pcsim::format_number(a.magnify));
  if (!(a.fps >= 1 && a.fps <= 120)) throw pcsim::InputError("--fps: expected 1 to 120");
  if (!(a.speed > 0 && a.speed <= 1e6)) throw pcsim::InputError("--speed: expected a number in (0, 1e6]");
  // The run's lock while it is read and the page written: a run replacing the directory now is
  // refused, and a directory being written by one refuses this.
  const pcsim::DirectoryLock lock(fs::path(a.dir).lexically_normal());
  if (owner == "modes" && !a.video.empty())
    throw pcsim::InputError("--video: a pcsim modes directory is animated as a page only (a mode at a "
                            "time, chosen on the page); drop --video");
  if (!a.video.empty()) check_video_path(a.video, dir);
  pcsim::animate::Scene scene = owner == "modes" ? pcsim::animate::read_modes_scene(dir, a.frames)
                                                 : pcsim::animate::read_scene(dir, a.frames);
  if (a.magnify > 0) scene.magnify = a.magnify;
  if (!a.video.empty()) {
    pcsim::animate::VideoOptions vo;
    vo.fps = a.fps;
    vo.speed = a.speed;
    pcsim::animate::write_video(scene, a.video, vo);
  }
  const fs::path page = dir / "animation.html";
  pcsim::write_file_atomically(page, pcsim::animate::animation_html(scene));
  if (!scene.mode_pages.empty()) {
    std::printf("pcsim animate: case '%s' (model '%s'), %zu modes, one cycle of %zu frames each\n",
                scene.title.c_str(), scene.model.c_str(), scene.mode_pages.size(), scene.mode_pages[0].count);
    std::printf("  wrote %s\n", page.string().c_str());
    return;
  }
  std::printf("pcsim animate: case '%s' (model '%s'), %zu frames of %zu rows, t = %s .. %s s%s\n",
              scene.title.c_str(), scene.model.c_str(), scene.t.size(), scene.rows,
              pcsim::format_significant(scene.t.front(), 6).c_str(),
              pcsim::format_significant(scene.t.back(), 6).c_str(),
              scene.magnify != 1 ? (", displacements magnified " + pcsim::format_significant(scene.magnify, 4) + "x").c_str() : "");
  std::printf("  wrote %s%s\n", page.string().c_str(), a.video.empty() ? "" : (" and " + a.video).c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<AnimateArgs>();
  CLI::App* sub = app.add_subcommand(
      "animate", "Draw a run (pcsim run / pcsim steady output; or the mode shapes of pcsim modes) by its model's [model.draw] table: "
                 "writes DIR/animation.html, one self-contained page (no network), and a video with --video");
  sub->add_option("dir", args->dir, "the run's output directory, e.g. out/sieve_1995")->required();
  sub->add_option("--video", args->video, "also render the frames to FILE.mp4 or FILE.gif with ffmpeg")
      ->type_name("FILE");
  sub->add_option("--frames", args->frames, "the page's frames at most (default 2000; events add theirs)");
  sub->add_option("--magnify", args->magnify,
                  "the displacement magnification about the moving mean shown first (default: the "
                  "drawing's magnify)");
  sub->add_option("--fps", args->fps, "video frames per second (default 25)");
  sub->add_option("--speed", args->speed, "video: seconds of motion per second of video (default 1)");
  sub->callback([args] { animate(*args); });
}

const bool registered = pcsim::cli::register_command(60, &setup);

}  // namespace
