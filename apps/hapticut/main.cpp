// hapticut: one executable with git-style subcommands (view, screenshot, run, info, convert, bench, assets, soak,
// devices).
#include <CLI/CLI.hpp>

#include <iostream>
#include <vector>

#include "commands.h"
#include "hapticut/common/temp_files.h"

int main(int argc, char** argv) {
    // No setlocale(LC_ALL, ""): output stays in the "C" locale, so numbers always print with a decimal point.
    // A signal that ends a command removes the temporary file it was writing; the target stays as it was.
    hapticut::removeTempFilesOnSignals();
    CLI::App app{"Hapticut: haptic soft-tissue simulator (mass-spring organ models, proxy haptics, cutting)",
                 "hapticut"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "hapticut 0.1.0");

    using hapticut::app::Command;
    std::vector<std::pair<CLI::App*, Command>> commands;
    for (auto add : {
#ifdef HAPTICUT_WITH_VIEWER
             hapticut::app::addViewCommand, hapticut::app::addScreenshotCommand,
#endif
             hapticut::app::addRunCommand, hapticut::app::addInfoCommand, hapticut::app::addConvertCommand,
             hapticut::app::addBenchCommand, hapticut::app::addAssetsCommand, hapticut::app::addSoakCommand,
             hapticut::app::addDevicesCommand}) {
        Command run = add(app);
        commands.emplace_back(app.get_subcommands({}).back(), std::move(run));
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    for (auto& [sub, run] : commands)
        if (sub->parsed()) {
            try {
                return run();
            } catch (const std::exception& e) {
                std::cerr << "hapticut: " << e.what() << "\n";
                return 1;
            }
        }
    return 1;
}
