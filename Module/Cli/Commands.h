#pragma once
/// @file Commands.h
/// @brief The commands of `tissuemosaic`, one file each. setupX adds command X to its parent (the tool, or the
/// `bench` and `synth` parents) with its options and a callback that runs it; errors are thrown
/// (tissuemosaic::Error, or UsageError for a command line that does not make sense) and reported by main().
#include <CLI/CLI.hpp>

namespace tissuemosaic::cli {

void setupStereo(CLI::App& tool);             ///< tissuemosaic stereo ...         (StereoCommand.cpp)
void setupTrack(CLI::App& tool);              ///< tissuemosaic track ...          (TrackCommand.cpp)
/// How a command set up on a parent is used: run when parsed, or only parsed (the batch checks each manifest row's
/// options with reconstruct's own parser before running any).
enum class CommandUse { Run, ParseOnly };

void setupReconstruct(CLI::App& tool, CommandUse use = CommandUse::Run);  ///< tissuemosaic reconstruct ... (ReconstructCommand.cpp)
void setupBatch(CLI::App& tool);              ///< tissuemosaic batch ...          (BatchCommand.cpp)
void setupParams(CLI::App& tool);             ///< tissuemosaic params ...         (ParamsCommand.cpp)
void setupRegister(CLI::App& tool);           ///< tissuemosaic register ...       (RegisterCommand.cpp, needs VTK)
void setupEval(CLI::App& tool);               ///< tissuemosaic eval ...           (EvalCommand.cpp, needs VTK)
void setupSynthPair(CLI::App& synth);         ///< tissuemosaic synth pair ...     (SynthCommand.cpp)
void setupSynthScan(CLI::App& synth);         ///< tissuemosaic synth scan ...     (SynthScanCommand.cpp)
void setupBenchStereo(CLI::App& bench);       ///< tissuemosaic bench stereo ...   (BenchStereoCommand.cpp)
void setupBenchTrack(CLI::App& bench);        ///< tissuemosaic bench track ...    (BenchTrackCommand.cpp)
void setupBenchReconstruct(CLI::App& bench);  ///< tissuemosaic bench reconstruct ... (BenchReconstructCommand.cpp)
void setupBenchPnp(CLI::App& bench);          ///< tissuemosaic bench pnp ...      (BenchPnpCommand.cpp)
void setupBenchOrb(CLI::App& bench);          ///< tissuemosaic bench orb ...      (BenchOrbCommand.cpp)

/// Adds a command to `parent` with the house's help layout: a one-line summary (listed by the parent's --help) and
/// `details` printed after the options (main() moves -h/--help last, under the common options).
CLI::App* addCommand(CLI::App& parent, const std::string& name, const std::string& summary,
                     const std::string& details);

}  // namespace tissuemosaic::cli
