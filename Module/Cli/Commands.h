#pragma once
/// @file Commands.h
/// @brief The sub-commands of `tissuemosaic`. Each takes the words after its name and returns the exit status;
/// errors are thrown as tissuemosaic::Error and reported by main().
#include <string>
#include <vector>

namespace tissuemosaic::cli {

using Words = std::vector<std::string>;

int runStereo(const Words& words);      ///< tissuemosaic stereo ...        (StereoCommand.cpp)
int runBenchStereo(const Words& words); ///< tissuemosaic bench stereo ...  (BenchStereoCommand.cpp)
int runBenchPnp(const Words& words);    ///< tissuemosaic bench pnp ...     (BenchPnpCommand.cpp)
int runBenchTrack(const Words& words);  ///< tissuemosaic bench track ...   (BenchTrackCommand.cpp)
int runBenchOrb(const Words& words);    ///< tissuemosaic bench orb ...     (BenchOrbCommand.cpp)
int runSynthPair(const Words& words);   ///< tissuemosaic synth pair ...    (SynthCommand.cpp)
int runSynthScan(const Words& words);   ///< tissuemosaic synth scan ...    (SynthScanCommand.cpp)
int runTrack(const Words& words);       ///< tissuemosaic track ...         (TrackCommand.cpp)
int runReconstruct(const Words& words); ///< tissuemosaic reconstruct ...   (ReconstructCommand.cpp)
int runBenchReconstruct(const Words& words);  ///< tissuemosaic bench reconstruct ... (BenchReconstructCommand.cpp)
int runRegister(const Words& words);    ///< tissuemosaic register ...      (RegisterCommand.cpp, needs VTK)
int runEval(const Words& words);        ///< tissuemosaic eval ...          (EvalCommand.cpp, needs VTK)

}  // namespace tissuemosaic::cli
