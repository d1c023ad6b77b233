#include "app/cli_options.h"
#include "app/cli_support.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace softtouch::cli {

std::string readNumber(const std::string& text, NumberRange range, double& value) {
    // The range's containment and wording are core's (FieldRange), so an option and a file say the same.
    const FieldRange field{"", "", range.min, range.max, "", range.minIncluded, range.whole};
    const bool bounded = std::isfinite(range.min) || std::isfinite(range.max);
    const auto number = parseNumber(text);
    if (!number || !field.contains(*number))
        return (number && bounded ? "must be " : "expects ") + field.describe() + ", got '" + text + "'";
    value = *number;
    return {};
}

CommandLine::Reader sizeReader(std::pair<int, int>& into) {
    return [&into](const std::string& text) {
        const auto size = parseSize(text);
        if (!size)
            return "expects WIDTHxHEIGHT with whole numbers in 16..8192, got '" + text + "'";
        into = *size;
        return std::string();
    };
}

CommandLine::CommandLine(std::string command, std::string about, std::string after)
    : m_command(std::move(command)), m_about(std::move(about)), m_after(std::move(after)) {}

CommandLine::Declared& CommandLine::declare(Declared::Kind kind, std::string name, Shown shown) {
    Declared& d = m_declared.emplace_back();
    d.kind = kind;
    d.name = std::move(name);
    d.shown = std::move(shown);
    return d;
}

void CommandLine::positional(std::string name, std::string& into, std::string help, bool optional) {
    declare(Declared::Kind::Positional, std::move(name), {"", std::move(help), !optional}).text = &into;
}

void CommandLine::positional(std::string name, std::string& into, Shown shown) {
    declare(Declared::Kind::Positional, std::move(name), std::move(shown)).text = &into;
}

void CommandLine::positionals(std::string name, std::vector<std::string>& into, std::string help, bool optional) {
    declare(Declared::Kind::Positionals, std::move(name), {"", std::move(help), !optional}).texts = &into;
}

void CommandLine::flag(std::string option, bool& into, std::string help) {
    declare(Declared::Kind::Flag, std::move(option), {"", std::move(help), false}).flag = &into;
}

void CommandLine::text(std::string option, std::string& into, Shown shown) {
    value(std::move(option), [&into](const std::string& v) {
        into = v;
        return std::string();
    }, std::move(shown));
}

void CommandLine::text(std::string option, std::optional<std::string>& into, Shown shown) {
    value(std::move(option), [&into](const std::string& v) {
        into = v;
        return std::string();
    }, std::move(shown));
}

void CommandLine::texts(std::string option, std::vector<std::string>& into, Shown shown) {
    declare(Declared::Kind::Values, std::move(option), std::move(shown)).texts = &into;
}

void CommandLine::number(std::string option, std::optional<double>& into, NumberRange range, Shown shown) {
    value(std::move(option), [&into, range](const std::string& v) {
        double n = 0.0;
        std::string problem = readNumber(v, range, n);
        if (problem.empty())
            into = n;
        return problem;
    }, std::move(shown));
}

void CommandLine::value(std::string option, Reader read, Shown shown) {
    declare(Declared::Kind::Value, std::move(option), std::move(shown)).read = std::move(read);
}

std::string CommandLine::named(const Declared& d) {
    if (d.kind == Declared::Kind::Positionals)
        return d.name + "...";
    if (d.kind == Declared::Kind::Positional)
        return d.shown.value.empty() ? d.name : d.shown.value;
    return d.shown.value.empty() ? d.name : d.name + " " + d.shown.value;
}

std::string CommandLine::inUsage(const Declared& d) { return d.shown.required ? named(d) : "[" + named(d) + "]"; }

std::string CommandLine::synopsis() const {
    std::string line = m_command;
    for (const Declared& d : m_declared)
        line += " " + inUsage(d);
    return line;
}

std::string helpEntry(std::string_view name, std::string_view text) {
    constexpr std::size_t kIndent = 20, kWidth = 100;
    std::string out = "  " + std::string(name);
    if (text.empty())
        return out + "\n";
    if (out.size() + 1 > kIndent)
        out += "\n" + std::string(kIndent, ' ');  // a long name: the text starts under the others' texts
    else
        out.resize(kIndent, ' ');
    std::size_t column = kIndent;
    bool first = true;
    while (!text.empty()) {
        const std::size_t space = text.find(' ');
        const std::string_view word = text.substr(0, space);
        if (!first && column + 1 + word.size() > kWidth) {
            out += "\n" + std::string(kIndent, ' ');
            column = kIndent;
        } else if (!first) {
            out += ' ';
            ++column;
        }
        out += word;
        column += word.size();
        first = false;
        text = space == std::string_view::npos ? std::string_view() : text.substr(space + 1);
    }
    return out + "\n";
}

std::string CommandLine::help() const {
    // The usage line wrapped under the command, as a long one reads in a terminal.
    std::string text = "Usage: softtouch-cli " + m_command;
    const std::size_t indent = text.size();  // continuation lines start under the command's first argument
    std::size_t column = text.size();
    for (const Declared& d : m_declared) {
        const std::string word = inUsage(d);
        if (column + 1 + word.size() > 110) {
            text += "\n" + std::string(indent, ' ');
            column = indent;
        }
        text += " " + word;
        column += 1 + word.size();
    }
    text += "\n\n" + m_about;
    if (!m_about.empty() && m_about.back() != '\n')
        text += "\n";
    bool any = false;
    for (const Declared& d : m_declared) {
        if (d.shown.help.empty())
            continue;
        if (!any)
            text += "\nArguments and options:\n";
        any = true;
        text += helpEntry(named(d), d.shown.help);
    }
    if (!m_after.empty())
        text += "\n" + m_after + (m_after.back() == '\n' ? "" : "\n");
    return text;
}

int CommandLine::usage(const std::string& problem) const { return usageError(problem, synopsis(), m_command); }

std::optional<int> CommandLine::parse(const std::vector<std::string>& args) {
    // Help wins over everything else on the line, as it did before there was a parser.
    if (std::any_of(args.begin(), args.end(), [](const std::string& a) { return a == "--help" || a == "-h"; })) {
        std::fputs(help().c_str(), stdout);
        return 0;
    }
    CLI::App app(m_about, m_command);
    app.set_help_flag();     // ours, above
    app.allow_extras();      // reported below, in our words
    // Values are read after the whole line is parsed, in the order the options were declared.
    std::vector<std::pair<const Declared*, std::vector<std::string>>> given;
    given.reserve(m_declared.size());
    for (const Declared& d : m_declared) {
        given.push_back({&d, {}});
        std::vector<std::string>& words = given.back().second;
        switch (d.kind) {
        case Declared::Kind::Positional:
            app.add_option(d.name, *d.text);
            break;
        case Declared::Kind::Positionals:
            app.add_option(d.name, words)->expected(0, -1);
            break;
        case Declared::Kind::Flag:
            app.add_flag(d.name, *d.flag);
            break;
        case Declared::Kind::Value:
        case Declared::Kind::Values:
            // One value per occurrence (a later word is never taken as a second value: a vector target lets
            // CLI11 take every following word up to the next option, so "--frames 5 SCENE" gave --frames the
            // scene); every occurrence kept.
            app.add_option(d.name, words)->expected(1)->allow_extra_args(false)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
            break;
        }
    }
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes the words last first
    try {
        app.parse(reversed);
    } catch (const CLI::ArgumentMismatch& e) {
        // CLI11 says "--out: 1 required TEXT missing": the option's name comes first.
        const std::string what = e.what();
        if (what.find(" required ") != std::string::npos && what.find(" missing") != std::string::npos)
            return usage(what.substr(0, what.find(':')) + ": needs a value");
        return usage(what);
    } catch (const CLI::ParseError& e) {
        return usage(e.what());
    }
    std::vector<std::string> rest = app.remaining();
    std::erase(rest, "--");  // CLI11 hands the words after it to the positionals but keeps the mark itself
    if (!rest.empty()) {
        const std::string& word = rest.front();
        if (word.size() > 1 && word[0] == '-')
            return usage("unknown option '" + word + "'" + m_unknownOptionNote);
        return usage("unexpected argument '" + word + "'");
    }
    for (const auto& [d, words] : given) {
        switch (d->kind) {
        case Declared::Kind::Positional:
            break;
        case Declared::Kind::Positionals:
        case Declared::Kind::Values:
            d->texts->insert(d->texts->end(), words.begin(), words.end());
            break;
        case Declared::Kind::Flag:
            break;
        case Declared::Kind::Value:
            if (!words.empty())
                if (const std::string problem = d->read(words.back()); !problem.empty())
                    return usage(d->name + ": " + problem);
            break;
        }
    }
    // What the usage line shows without brackets must be there ("bake needs --out FILE").
    for (const auto& [d, words] : given) {
        const bool missing = d->kind == Declared::Kind::Positional ? d->text->empty()
                           : d->kind == Declared::Kind::Flag       ? false
                                                                   : words.empty();
        if (d->shown.required && missing)
            return usage(m_command + " needs " + (d->kind == Declared::Kind::Positionals ? "at least one " + d->name : named(*d)));
    }
    return std::nullopt;
}

}  // namespace softtouch::cli
