// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// bimslam: the host tool. Offline work on sessions, BIM models and captures.
#include <CLI/CLI.hpp>

#include "host_tools/cli/command.hpp"

int main(int argc, char** argv) {
    CLI::App app{
        "bimslam: LiDAR mapping against a BIM model (host tools).\n"
        "Run 'bimslam <command> --help' for the options of a command."};
    app.require_subcommand(1);
    app.set_version_flag("--version", "bimslam 0.1.0");
    int exit_code = bimslam::cli::kExitOk;
    bimslam::cli::AddCanCommands(app, exit_code);
    bimslam::cli::AddDemoCommand(app, exit_code);
    bimslam::cli::AddOusterCommands(app, exit_code);
    bimslam::cli::AddSessionCommands(app, exit_code);
    auto* bim = app.add_subcommand("bim", "Building models (IFC): inspect, export, sample, plan");
    bim->require_subcommand(1);
    bimslam::cli::AddBimCommands(*bim, exit_code);
    bimslam::cli::AddBimSampleCommand(*bim, exit_code);
    bimslam::cli::AddBimPlanCommand(*bim, exit_code);
    bimslam::cli::AddBimStairsCommand(*bim, exit_code);
    bimslam::cli::AddBim2SessionCommand(app, exit_code);
    bimslam::cli::AddSimulateCommand(app, exit_code);
    bimslam::cli::AddOdometryCommand(app, exit_code);
    bimslam::cli::AddEvaluateCommand(app, exit_code);
    bimslam::cli::AddAnchorCommand(app, exit_code);
    bimslam::cli::AddChangesCommand(app, exit_code);
    bimslam::cli::AddMapCommand(app, exit_code);
    bimslam::cli::AddRigMapCommand(app, exit_code);
    bimslam::cli::AddLocalizeCommand(app, exit_code);
    bimslam::cli::AddLiveCommand(app, exit_code);
    bimslam::cli::AddBcfCommands(app, exit_code);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 prints help and usage errors itself; usage errors exit 2 (its default is 106+).
        const int code = app.exit(e);
        return code == 0 ? 0 : bimslam::cli::kExitBadInput;
    }
    return exit_code;
}
