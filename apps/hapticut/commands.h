// The subcommands of the hapticut executable; each adds itself to the CLI and runs when chosen.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hapticut::app {

/// Registers a subcommand; the returned function runs it after parsing and gives the exit code.
using Command = std::function<int()>;

Command addRunCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);
Command addBenchCommand(CLI::App& app);
Command addAssetsCommand(CLI::App& app);
Command addSoakCommand(CLI::App& app);
Command addDevicesCommand(CLI::App& app);
/// batch and plot: the package's Python (hapticut.batch, hapticut.plot) run with the arguments as given.
Command addBatchCommand(CLI::App& app);
Command addPlotCommand(CLI::App& app);
Command addAssessCommand(CLI::App& app);

/// `python3 -m hapticut.cli command args` with the package's folder on its path: in place of this process
/// (which then returns only on failure), or as a child waited for. Its exit code, or 1 when it cannot start.
enum class PythonProcess { Replace, Wait };
int runPythonCommand(const std::string& command, const std::vector<std::string>& args, PythonProcess how);
#ifdef HAPTICUT_WITH_VIEWER
Command addViewCommand(CLI::App& app);
Command addScreenshotCommand(CLI::App& app);
#endif

}  // namespace hapticut::app
