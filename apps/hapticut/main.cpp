// hapticut: one executable with git-style subcommands (view, screenshot, run, info, convert, bench, assets, soak,
// devices, batch, plot, assess).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <regex>
#include <string>
#include <vector>

#include "commands.h"
#include "hapticut/common/temp_files.h"
#include "provenance.h"

namespace {

/// Exit status for arguments the command cannot take, as docs/commands.md promises.
constexpr int kBadArguments = 2;

/// Edits from one word to the other (insert, delete, replace, swap two neighbours).
std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

/// "hapticut: 'viwe' is not a command; did you mean 'view'?" and the commands there are.
int unknownCommand(const CLI::App& app, const std::string& word) {
    std::string nearest, names;
    std::size_t best = 3;  // further than two edits is no longer a typo
    for (const CLI::App* sub : app.get_subcommands({})) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        if (const std::size_t d = editDistance(word, sub->get_name()); d < best) best = d, nearest = sub->get_name();
    }
    std::cerr << "hapticut: '" << word << "' is not a command"
              << (nearest.empty() ? "" : "; did you mean '" + nearest + "'?") << "\ncommands: " << names
              << "\nRun with --help for more information.\n";
    return kBadArguments;
}

/// CLI11's message for a value outside an option's range, said as a scene file says it: a value that
/// is no number at all is named as such instead of as out of range.
std::string plainMessage(const std::string& what) {
    static const std::regex range(R"(^(--?[\w-]+): Value (.*) not in range (\S+) to (\S+)$)");
    std::smatch m;
    if (!std::regex_match(what, m, range)) return what;
    auto shortNumber = [](const std::string& text) {
        try {
            std::size_t used = 0;
            const double v = std::stod(text, &used);
            char out[32];
            std::snprintf(out, sizeof out, "%g", v);
            return used == text.size() ? std::string(out) : text;
        } catch (const std::exception&) {
            return text;
        }
    };
    const std::string value = m[2];
    std::size_t used = 0;
    bool number = false;
    try {
        std::stod(value, &used);
        number = used == value.size();
    } catch (const std::exception&) {}
    if (!number) return std::string(m[1]) + ": expected a number, found '" + value + "'";
    return std::string(m[1]) + ": " + value + " is out of range; allowed: " + shortNumber(m[3]) + " to " +
           shortNumber(m[4]);
}

}  // namespace

int main(int argc, char** argv) {
    // No setlocale(LC_ALL, ""): output stays in the "C" locale, so numbers always print with a decimal point.
    // A signal that ends a command removes the temporary file it was writing; the target stays as it was.
    hapticut::removeTempFilesOnSignals();
    hapticut::app::recordCommandLine(argc, argv);
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
             hapticut::app::addDevicesCommand, hapticut::app::addBatchCommand, hapticut::app::addPlotCommand,
             hapticut::app::addAssessCommand}) {
        Command run = add(app);
        commands.emplace_back(app.get_subcommands({}).back(), std::move(run));
    }

    if (argc > 1 && argv[1][0] != '-') {
        const std::string word = argv[1];
        const auto subs = app.get_subcommands({});
        if (std::none_of(subs.begin(), subs.end(), [&](const CLI::App* sub) { return sub->check_name(word); }))
            return unknownCommand(app, word);
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Every other parse error is a mistake in the arguments: said plainly, with status 2.
        std::cerr << plainMessage(e.what()) << "\nRun with --help for more information.\n";
        return kBadArguments;
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
