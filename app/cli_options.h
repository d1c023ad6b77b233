#pragma once
/// How every subcommand of softtouch-cli and softtouch-bench reads its command line: the options are
/// declared, each with how its value is read and checked, and CLI11 (Debian's libcli11-dev) parses them
/// (`--out x`, `--out=x`, `--` before a file named like an option, a negative number as a value). One rule
/// for every command, tested as a table (tests/cli, helpAndUsage):
/// - `--help` or `-h` anywhere prints the command's help and exits 0;
/// - anything else wrong with the command line is bad usage, exit 2: "softtouch-cli: PROBLEM", the
///   command's usage line (app/cli_usage.h) and where its help is (usageError). PROBLEM names the option
///   first: "--fps: expects a number, got 'abc'", "--out: needs a value", "unknown option '--bogus'",
///   "unexpected argument 'x'";
/// - a failure of the work itself exits 1 (fail()).
/// CLI11 stays inside cli_options.cpp: its header is large, and the commands only declare.

#include "core/base/ranges.h"

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace softtouch::cli {

/// The numbers an option takes. Values outside, non-numbers and non-finite values are bad usage.
struct NumberRange {
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    bool whole = false;         ///< Whole numbers only.
    bool minIncluded = true;    ///< False: min itself is out ("(0, 3600]").
};

/// One subcommand's command line.
class CommandLine {
public:
    /// Reads one value: empty when it is fine (and stored), else what is wrong with it ("expects …, got '…'"),
    /// which the parse reports after the option's name.
    using Reader = std::function<std::string(const std::string& value)>;

    /// `command`: as typed after the program ("bake"); `help`: printed for --help.
    CommandLine(std::string command, std::string help);

    /// The next word that is not an option, into `into` (a SCENE). Words beyond the declared ones are
    /// "unexpected argument"s, unless a positionals() takes them.
    void positional(std::string name, std::string& into);
    /// Every remaining such word.
    void positionals(std::string name, std::vector<std::string>& into);
    /// A switch with no value.
    void flag(std::string option, bool& into);
    /// An option with a text value; given twice, the last one counts.
    void text(std::string option, std::string& into);
    void text(std::string option, std::optional<std::string>& into);
    /// An option that may be given again, each time with one value.
    void texts(std::string option, std::vector<std::string>& into);
    /// A number within `range`.
    void number(std::string option, std::optional<double>& into, NumberRange range);
    /// A number within a setting's range as core declares it (core/base/ranges.h), so the option and the project
    /// file accept the same values.
    void number(std::string option, std::optional<double>& into, const FieldRange& range) {
        number(std::move(option), into, NumberRange{range.low, range.high, range.whole, range.lowIncluded});
    }
    /// A value read and checked by `read`.
    void value(std::string option, Reader read);

    /// Parses `args` (the words after the command). Nothing when the command goes on; otherwise the exit
    /// status to return at once: 0 after printing the help, 2 after reporting bad usage.
    std::optional<int> parse(const std::vector<std::string>& args);

    /// Reports bad usage found after parsing (a missing --out, options that exclude each other): exit 2.
    int usage(const std::string& problem) const;

    /// Appended to the "unknown option" problem (validate: how to name a file that starts with '-').
    void setUnknownOptionNote(std::string note) { m_unknownOptionNote = std::move(note); }

private:
    struct Declared {
        enum class Kind { Positional, Positionals, Flag, Value, Values } kind = Kind::Value;
        std::string name;
        std::string* text = nullptr;
        std::vector<std::string>* texts = nullptr;
        bool* flag = nullptr;
        Reader read;
    };
    Declared& declare(Declared::Kind kind, std::string name);
    std::string m_command;
    std::string m_help;
    std::string m_unknownOptionNote;
    std::vector<Declared> m_declared;
};

/// A reader of "WIDTHxHEIGHT" in whole pixels, 16..8192 each (picture and video sizes), into `into`.
CommandLine::Reader sizeReader(std::pair<int, int>& into);

/// "expects a whole number in [1, 20], got '0'" and the like: what is wrong with `text` as a number in
/// `range`, or empty when it is one (then stored in `value`).
std::string readNumber(const std::string& text, NumberRange range, double& value);

}  // namespace softtouch::cli
