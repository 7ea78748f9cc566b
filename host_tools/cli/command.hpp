// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The `bimslam` command: shared conventions of its subcommands (DESIGN.md, "Conventions"):
// exit 0 on success, 1 on a failure while working, 2 on bad usage or bad input; errors go to
// stderr naming the file and what is wrong; --json where a script would want the output.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace bimslam::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

// Runs a subcommand body, turning exceptions into a message on stderr and the exit code above.
int Run(const std::function<int()>& body);

// v with `digits` digits after the point (std::fixed), for the summaries commands print.
std::string Fixed(double v, int digits);

// Each file registers its subcommands; the callback stores the exit code in `exit_code`.
void AddSessionCommands(CLI::App& app, int& exit_code);
void AddCanCommands(CLI::App& app, int& exit_code);
// `can` is the `bimslam can` subcommand: adds `bimslam can highstate`.
void AddHighStateCommand(CLI::App& can, int& exit_code);
void AddDemoCommand(CLI::App& app, int& exit_code);
void AddOusterCommands(CLI::App& app, int& exit_code);
// `ouster` is the `bimslam ouster` subcommand: adds `bimslam ouster replay`.
void AddOusterReplayCommand(CLI::App& ouster, int& exit_code);
// `bim` is the `bimslam bim` subcommand: adds `bimslam bim sample`.
void AddBimSampleCommand(CLI::App& bim, int& exit_code);
// `bim` is the `bimslam bim` subcommand: adds `bimslam bim info` and `bimslam bim mesh`.
void AddBimCommands(CLI::App& bim, int& exit_code);
void AddBimPlanCommand(CLI::App& bim, int& exit_code);
// `bimslam bim stairs`: the walkable 3D graph (bim/stairs.hpp).
void AddBimStairsCommand(CLI::App& bim, int& exit_code);
void AddBim2SessionCommand(CLI::App& app, int& exit_code);
void AddSimulateCommand(CLI::App& app, int& exit_code);
void AddOdometryCommand(CLI::App& app, int& exit_code);
void AddEvaluateCommand(CLI::App& app, int& exit_code);
void AddAnchorCommand(CLI::App& app, int& exit_code);
void AddChangesCommand(CLI::App& app, int& exit_code);
// `bimslam map` and `bimslam report`.
void AddMapCommand(CLI::App& app, int& exit_code);
// `bimslam rig-map`: the rig's map package (algorithms/localization/rig_map.hpp).
void AddRigMapCommand(CLI::App& app, int& exit_code);
// `bimslam localize`: a session through the rig's relocaliser (localization/relocalizer.hpp).
void AddLocalizeCommand(CLI::App& app, int& exit_code);
// `bimslam live`: bim_pose_t on the storey's plan (host_tools/live).
void AddLiveCommand(CLI::App& app, int& exit_code);
// `bimslam bcf info`: a BCF file read back (host_tools/changes/bcf_reader.hpp).
void AddBcfCommands(CLI::App& app, int& exit_code);

}  // namespace bimslam::cli
