// tissuemosaic: the headless command-line tool. Entry point only: each command lives in its own file.
#include "Commands.h"
#include "Core/Error.h"

#include <opencv2/core/utility.hpp>

#include <functional>
#include <iostream>
#include <map>

using namespace tissuemosaic;

namespace {

const char* const usage = R"(usage: tissuemosaic COMMAND [options]

commands:
  stereo       --left L.png --right R.png --out d.pfm [--min-disparity A] [--max-disparity B]
               [--calib rig.yml] [--cloud cloud.ply] [--device cpu|cuda|auto] [--params p.yml]
               [--method paper|ad-census] [--explain explain.json]
               left-view disparity of one stereo pair (PFM, NaN = no estimate), optionally a coloured cloud
  synth pair   --out DIR [--seed S] [--width W] [--height H] [--lighting standard|realistic]
               a synthetic stereo pair with calibration and ground truth
  synth scan   --out DIR [--frames N] [--seed S] [--width W] [--height H] [--lighting standard|realistic]
               a synthetic scanning video (rectified frames) with trajectory, surface and depth ground truth
  track        --left-frames DIR --right-frames DIR --calib rig.yml --out trajectory.txt
               [--rectified] [--device cpu|cuda|auto] [--start-tum T.txt] [--groundtruth T.txt]
               camera tracking (ORB, histogram voting, DynamicR1PPnP) to a TUM trajectory
  reconstruct  (--left-frames DIR --right-frames DIR | --left-video L --right-video R | --video SBS)
               (--calib rig.yml [--rectified] | --focal-px F --baseline-mm B) --out model.ply|.vtp
               [--trajectory traj.txt] [--device cpu|cuda|auto] [--snapshot view.png] [--params p.yml]
               the whole pipeline: a fused, textured point model, key-frame trajectory and timing table
  register     --model model.ply --target ct.stl --out-transform t.tfm --report report.json
               [--landmarks pairs.mrk.json | --model-landmarks A --target-landmarks B] [--scale] [--icp]
               [--max-icp-iterations N] [--out-model registered.vtp] [--distances d.csv] [--histogram h.png]
               registration to a CT/MR surface model (landmarks, ICP) and its accuracy (RMSE, histogram)
  eval         --model model.ply --reference surface.ply [--trajectory t.txt --reference-trajectory gt.txt]
               [--align icp] [--coverage-radius-mm R] [--time-tolerance S] [--json]
               a reconstruction against a known surface: distances (RMSE, mean, p95), coverage, ATE and RPE
  bench stereo [--width 960] [--height 540] [--device cpu|cuda] [--repeats N] [--method paper|ad-census]
               median milliseconds per stereo stage as JSON
  bench track  [--width 960] [--height 540] [--frames 20] [--device cpu|cuda] [--features opencv|tissuemosaic]
               median milliseconds per frame of ORB + voting and DynamicR1PPnP as JSON
  bench reconstruct [--width 960] [--height 540] [--frames 60] [--device cpu|cuda]
               median milliseconds per stage and per key/other frame of the whole pipeline as JSON
  bench pnp    [--repeats N]
               DynamicR1PPnP against OpenCV solvePnPRansac as JSON
  bench orb    [--width 960] [--height 540] [--device cpu|cuda] [--repeats N]
               median milliseconds of ORB extraction and Hamming matching as JSON

Run a command with --help for its details.
)";

}  // namespace

int main(int argc, char** argv) {
  cli::Words words(argv + 1, argv + argc);
  if (words.empty() || words[0] == "--help" || words[0] == "-h" || words[0] == "help") {
    std::cout << usage;
    return words.empty() ? 2 : 0;
  }
  const std::map<std::string, std::function<int(const cli::Words&)>> commands = {
      {"bench stereo", cli::runBenchStereo},
      {"bench pnp", cli::runBenchPnp},
      {"bench track", cli::runBenchTrack},
      {"bench orb", cli::runBenchOrb},
      {"bench reconstruct", cli::runBenchReconstruct},
#if !defined(TM_BENCH_ONLY)
      {"stereo", cli::runStereo},
      {"synth pair", cli::runSynthPair},
      {"synth scan", cli::runSynthScan},
      {"track", cli::runTrack},
      {"reconstruct", cli::runReconstruct},
#if defined(TM_WITH_REGISTRATION)
      {"register", cli::runRegister},
      {"eval", cli::runEval},
#else
      {"register", [](const cli::Words&) -> int {
         throw Error("this build has no registration: it needs VTK (configure with -DTM_WITH_GUI=ON)");
       }},
      {"eval", [](const cli::Words&) -> int {
         throw Error("this build has no evaluation: it needs VTK (configure with -DTM_WITH_GUI=ON)");
       }},
#endif
#endif
  };
  std::string name = words[0];
  std::size_t consumed = 1;
  if (!commands.count(name) && words.size() > 1 && commands.count(name + " " + words[1])) {
    name += " " + words[1];
    consumed = 2;
  }
  const auto command = commands.find(name);
  if (command == commands.end()) {
    std::cerr << "tissuemosaic: unknown command '" << name << "'\n\n" << usage;
    return 2;
  }
  try {
    return command->second(cli::Words(words.begin() + static_cast<long>(consumed), words.end()));
  } catch (const Error& error) {
    std::cerr << "tissuemosaic " << name << ": error: " << error.what() << "\n";
    return 1;
  } catch (const cv::Exception& error) {
    std::cerr << "tissuemosaic " << name << ": OpenCV error: " << error.what() << "\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "tissuemosaic " << name << ": error: " << error.what() << "\n";
    return 1;
  }
}
