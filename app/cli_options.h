#pragma once
/// How every subcommand of softtouch-cli and softtouch-bench reads its command line: the options are
/// declared, each with how its value is read and checked and how it is shown, and CLI11 (Debian's
/// libcli11-dev) parses them (`--out x`, `--out=x`, `--` before a file named like an option, a negative number
/// as a value). The command's usage line, its --help and every usage error are made from the declarations, so
/// an option is named, shown and explained in one place. One rule for every command, tested as a table
/// (tests/cli, helpAndUsage):
/// - `--help` or `-h` anywhere prints the command's help and exits 0;
/// - anything else wrong with the command line is bad usage, exit 2: "softtouch-cli: PROBLEM", the
///   command's usage line and where its help is (usage()). PROBLEM names the option first: "--fps: expects a
///   number, got 'abc'", "--out: needs a value", "unknown option '--bogus'", "unexpected argument 'x'",
///   "bake needs --out FILE";
/// - a failure of the work itself exits 1 (fail()).
/// CLI11 stays inside cli_options.cpp: its header is large, and the commands only declare.

#include "core/base/ranges.h"

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
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

/// How an option shows in the usage line and the help.
struct Shown {
    std::string value;      ///< Its value's name in the usage line ("FILE", "N"); empty for a flag.
    std::string help;       ///< What it does, for --help (wrapped there).
    bool required = false;  ///< Shown without brackets, and missing it is bad usage ("bake needs --out FILE").
};

/// One subcommand's command line.
class CommandLine {
public:
    /// Reads one value: empty when it is fine (and stored), else what is wrong with it ("expects …, got '…'"),
    /// which the parse reports after the option's name.
    using Reader = std::function<std::string(const std::string& value)>;

    /// `command`: as typed after the program ("bake"); `about`: what the command does, printed by --help
    /// between the usage line and the options; `after`: printed after the options (exit status, notes).
    CommandLine(std::string command, std::string about, std::string after = {});

    /// The next word that is not an option, into `into` (a SCENE); required unless `optional`. Words beyond the
    /// declared ones are "unexpected argument"s, unless a positionals() takes them.
    void positional(std::string name, std::string& into, std::string help, bool optional = false);
    /// The same, shown in the usage line as `shown.value` instead of its name (a verb: "plan|run|slurm|check").
    void positional(std::string name, std::string& into, Shown shown);
    /// Every remaining such word (at least one unless `optional`).
    void positionals(std::string name, std::vector<std::string>& into, std::string help, bool optional = false);
    /// A switch with no value.
    void flag(std::string option, bool& into, std::string help);
    /// An option with a text value; given twice, the last one counts.
    void text(std::string option, std::string& into, Shown shown);
    void text(std::string option, std::optional<std::string>& into, Shown shown);
    /// An option that may be given again, each time with one value.
    void texts(std::string option, std::vector<std::string>& into, Shown shown);
    /// A number within `range`.
    void number(std::string option, std::optional<double>& into, NumberRange range, Shown shown);
    /// A number within a setting's range as core declares it (core/base/ranges.h), so the option and the project
    /// file accept the same values.
    void number(std::string option, std::optional<double>& into, const FieldRange& range, Shown shown) {
        number(std::move(option), into, NumberRange{range.low, range.high, range.whole, range.lowIncluded}, std::move(shown));
    }
    /// A value read and checked by `read`.
    void value(std::string option, Reader read, Shown shown);

    /// Parses `args` (the words after the command). Nothing when the command goes on; otherwise the exit
    /// status to return at once: 0 after printing the help, 2 after reporting bad usage (a required option or
    /// argument missing included).
    std::optional<int> parse(const std::vector<std::string>& args);

    /// Reports bad usage found after parsing (options that exclude each other, a value that does not suit
    /// another): exit 2.
    int usage(const std::string& problem) const;

    /// What follows "softtouch-cli " in the usage line: the command, then every declaration in order, the
    /// optional ones in brackets ("bake SCENE --out FILE [--clip NAME] ...").
    std::string synopsis() const;
    /// The whole --help text.
    std::string help() const;

    /// Appended to the "unknown option" problem (validate: how to name a file that starts with '-').
    void setUnknownOptionNote(std::string note) { m_unknownOptionNote = std::move(note); }

private:
    struct Declared {
        enum class Kind { Positional, Positionals, Flag, Value, Values } kind = Kind::Value;
        std::string name;
        Shown shown;
        std::string* text = nullptr;
        std::vector<std::string>* texts = nullptr;
        bool* flag = nullptr;
        Reader read;
    };
    Declared& declare(Declared::Kind kind, std::string name, Shown shown);
    /// "--out FILE", "SCENE", "FILE...": a declaration as the usage line and the help name it.
    static std::string named(const Declared& d);
    /// named(), in brackets unless required: a declaration's word in the usage line.
    static std::string inUsage(const Declared& d);
    std::string m_command;
    std::string m_about;
    std::string m_after;
    std::string m_unknownOptionNote;
    std::vector<Declared> m_declared;
};

/// "  NAME              text…": one entry of a help's list, the text wrapped at 100 columns under itself (on
/// the next line when NAME is too long to leave room).
std::string helpEntry(std::string_view name, std::string_view text);

/// A reader of "WIDTHxHEIGHT" in whole pixels, 16..8192 each (picture and video sizes), into `into`.
CommandLine::Reader sizeReader(std::pair<int, int>& into);

/// "expects a whole number in [1, 20], got '0'" and the like: what is wrong with `text` as a number in
/// `range`, or empty when it is one (then stored in `value`).
std::string readNumber(const std::string& text, NumberRange range, double& value);

}  // namespace softtouch::cli
