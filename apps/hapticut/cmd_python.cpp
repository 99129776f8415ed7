// `hapticut batch` and `hapticut plot`: the front doors to the package's Python (hapticut.cli, which
// runs hapticut.batching and hapticut.plotting), which has Dask and matplotlib. The arguments go through as given; the
// Python side checks them and answers --help.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"

namespace hapticut::app {

namespace {

namespace fs = std::filesystem;

#ifdef HAPTICUT_PYTHON_EXECUTABLE
/// The folder that holds the `hapticut` package: beside an installed executable (PREFIX/bin and
/// PREFIX/lib/python3.X/dist-packages), else the build tree's.
std::optional<fs::path> packageFolder() {
    std::error_code error;
    const fs::path executable = fs::read_symlink("/proc/self/exe", error);
    std::vector<fs::path> candidates;
    if (!error) candidates.push_back(executable.parent_path().parent_path() / HAPTICUT_PYTHON_INSTALL_DIR);
    candidates.emplace_back(HAPTICUT_PYTHON_BUILD_DIR);
    for (const fs::path& folder : candidates)
        if (fs::is_regular_file(folder / "hapticut" / "__init__.py", error)) return folder;
    return std::nullopt;
}
#endif

}  // namespace

int runPythonCommand(const std::string& command, const std::vector<std::string>& args, PythonProcess how) {
#ifndef HAPTICUT_PYTHON_EXECUTABLE
    (void)args, (void)how;
    std::cerr << "hapticut " << command
              << ": runs in Python, and this build has no Python module (scripts/install-deps installs python3-dev, "
                 "pybind11-dev and python3-numpy; then build again)\n";
    return 1;
#else
    const std::optional<fs::path> folder = packageFolder();
    if (!folder) {
        std::cerr << "hapticut " << command << ": the hapticut Python package is neither installed beside this "
                  << "executable nor in " << HAPTICUT_PYTHON_BUILD_DIR << " (build the target _hapticut)\n";
        return 1;
    }
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = folder->string() + (old && *old ? ":" + std::string(old) : "");
    ::setenv("PYTHONPATH", path.c_str(), 1);
    const char* python = std::getenv("HAPTICUT_PYTHON");
    if (!python || !*python) python = HAPTICUT_PYTHON_EXECUTABLE;
    std::vector<std::string> words{python, "-m", "hapticut.cli", command};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    std::cout.flush();
    if (how == PythonProcess::Replace) {
        ::execv(python, argv.data());
        std::cerr << "hapticut " << command << ": could not start " << python << ": " << std::strerror(errno) << "\n";
        return 1;
    }
    pid_t child = 0;
    if (const int error = ::posix_spawn(&child, python, nullptr, nullptr, argv.data(), environ)) {
        std::cerr << "hapticut " << command << ": could not start " << python << ": " << std::strerror(error) << "\n";
        return 1;
    }
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {}
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
#endif
}

namespace {

/// A subcommand whose every argument, --help included, is the Python module's.
Command addPythonCommand(CLI::App& app, const std::string& name, const std::string& description) {
    CLI::App* sub = app.add_subcommand(name, description);
    sub->set_help_flag();
    sub->allow_extras();
    sub->prefix_command();
    return [sub, name] { return runPythonCommand(name, sub->remaining(), PythonProcess::Replace); };
}

}  // namespace

Command addBatchCommand(CLI::App& app) {
    return addPythonCommand(app, "batch",
                            "Run every combination of a spec's sweep on a Dask cluster (a local one by default); "
                            "hapticut batch --help for its options");
}

Command addPlotCommand(CLI::App& app) {
    return addPythonCommand(app, "plot",
                            "Plot a force log or report (force against time) or a batch's results (a metric against "
                            "each swept parameter) as PNG; hapticut plot --help for its options");
}

}  // namespace hapticut::app
