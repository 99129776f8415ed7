// LineReader and locale-independent number parsing and formatting.
#include "hapticut/common/line_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace hapticut {

namespace {
constexpr std::size_t kMaxLineLength = 64 * 1024;

std::string quoted(std::string_view s) {
    constexpr std::size_t kShown = 40;
    std::string out = "'";
    for (char c : s.substr(0, kShown))
        out += (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) ? '?' : c;
    if (s.size() > kShown) out += "...";
    return out + "'";
}
}  // namespace

LineReader::LineReader(std::string_view text) : text_(text) {
    totalLines_ = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
}

bool LineReader::next() {
    while (pos_ < text_.size()) {
        const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
        raw_ = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
        ++line_;
        if (!raw_.empty() && raw_.back() == '\r') raw_.remove_suffix(1);
        if (raw_.size() > kMaxLineLength) fail("line is longer than " + std::to_string(kMaxLineLength) + " characters");
        tokens_.clear();
        std::size_t i = 0;
        while (i < raw_.size()) {
            while (i < raw_.size() && (raw_[i] == ' ' || raw_[i] == '\t')) ++i;
            const std::size_t start = i;
            while (i < raw_.size() && raw_[i] != ' ' && raw_[i] != '\t') ++i;
            if (i > start) tokens_.push_back(raw_.substr(start, i - start));
        }
        if (!tokens_.empty() && tokens_[0].front() != '#') return true;
    }
    raw_ = {};
    tokens_.clear();
    return false;
}

void LineReader::expectTokens(std::size_t n, std::string_view what) const {
    if (tokens_.size() != n)
        fail("expected " + std::string(what) + " (" + std::to_string(n) + " values), found " +
             std::to_string(tokens_.size()) + " value" + (tokens_.size() == 1 ? "" : "s") + ": " + quoted(raw_));
}

double LineReader::number(std::size_t i, std::string_view what) const {
    double v = 0;
    if (!parseFiniteDouble(tokens_[i], v))
        fail("expected a finite number for " + std::string(what) + ", found " + quoted(tokens_[i]));
    return v;
}

std::uint64_t LineReader::count(std::size_t i, std::string_view what) const {
    std::uint64_t v = 0;
    if (!parseUnsigned(tokens_[i], v))
        fail("expected a non-negative whole number for " + std::string(what) + ", found " + quoted(tokens_[i]));
    return v;
}

bool parseFiniteDouble(std::string_view s, double& out) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars rejects a leading '+'
    const char* end = s.data() + s.size();
    const auto [ptr, ec] = std::from_chars(s.data(), end, out);
    return ec == std::errc() && ptr == end && !s.empty() && std::isfinite(out);
}

bool parseUnsigned(std::string_view s, std::uint64_t& out) {
    const char* end = s.data() + s.size();
    const auto [ptr, ec] = std::from_chars(s.data(), end, out);
    return ec == std::errc() && ptr == end && !s.empty();
}

std::string formatDouble(double value) {
    char buf[32];
    const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);
    return std::string(buf, ec == std::errc() ? ptr : buf);
}

std::string threeDigits(double value) {
    char buf[32];
    const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, 3);
    return std::string(buf, ec == std::errc() ? ptr : buf);
}

}  // namespace hapticut
