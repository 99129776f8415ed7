// LineReader: splits text into lines and whitespace-separated tokens, and parses numbers
// independently of the C locale, throwing ParseFailure with the line number on bad input.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hapticut {

/// Thrown inside parsers only; every public parser catches it and returns an Error.
struct ParseFailure {
    int line;
    std::string message;
};

class LineReader {
public:
    explicit LineReader(std::string_view text);

    /// Advances to the next line that is neither blank nor a '#' comment. False at the end.
    bool next();
    int line() const { return line_; }
    const std::vector<std::string_view>& tokens() const { return tokens_; }
    std::string_view token(std::size_t i) const { return tokens_[i]; }
    std::string_view rawLine() const { return raw_; }
    /// Lines not yet read, an upper bound on how many records can still follow.
    std::size_t linesLeft() const { return totalLines_ - static_cast<std::size_t>(line_); }

    [[noreturn]] void fail(std::string message) const { throw ParseFailure{line_, std::move(message)}; }
    /// Requires the current line to hold exactly n tokens; `what` names them for the message.
    void expectTokens(std::size_t n, std::string_view what) const;

    double number(std::size_t i, std::string_view what) const;
    std::uint64_t count(std::size_t i, std::string_view what) const;

private:
    std::string_view text_;
    std::size_t pos_ = 0, totalLines_ = 0;
    int line_ = 0;
    std::string_view raw_;
    std::vector<std::string_view> tokens_;
};

/// Locale-independent parse of a finite double; false if `s` is not entirely a finite number.
bool parseFiniteDouble(std::string_view s, double& out);
/// Locale-independent parse of an unsigned integer; false on anything else or overflow.
bool parseUnsigned(std::string_view s, std::uint64_t& out);
/// Shortest text that reads back to exactly the same double (round-trip exact, no locale).
std::string formatDouble(double value);
/// Three significant digits (0.000123, 45.6, 1.23e+07), no locale: for figures a person reads.
std::string threeDigits(double value);

}  // namespace hapticut
