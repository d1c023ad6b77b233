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

CommandLine::CommandLine(std::string command, std::string help) : m_command(std::move(command)), m_help(std::move(help)) {}

CommandLine::Declared& CommandLine::declare(Declared::Kind kind, std::string name) {
    Declared& d = m_declared.emplace_back();
    d.kind = kind;
    d.name = std::move(name);
    return d;
}

void CommandLine::positional(std::string name, std::string& into) {
    declare(Declared::Kind::Positional, std::move(name)).text = &into;
}

void CommandLine::positionals(std::string name, std::vector<std::string>& into) {
    declare(Declared::Kind::Positionals, std::move(name)).texts = &into;
}

void CommandLine::flag(std::string option, bool& into) {
    declare(Declared::Kind::Flag, std::move(option)).flag = &into;
}

void CommandLine::text(std::string option, std::string& into) {
    value(std::move(option), [&into](const std::string& v) {
        into = v;
        return std::string();
    });
}

void CommandLine::text(std::string option, std::optional<std::string>& into) {
    value(std::move(option), [&into](const std::string& v) {
        into = v;
        return std::string();
    });
}

void CommandLine::texts(std::string option, std::vector<std::string>& into) {
    declare(Declared::Kind::Values, std::move(option)).texts = &into;
}

void CommandLine::number(std::string option, std::optional<double>& into, NumberRange range) {
    value(std::move(option), [&into, range](const std::string& v) {
        double n = 0.0;
        std::string problem = readNumber(v, range, n);
        if (problem.empty())
            into = n;
        return problem;
    });
}

void CommandLine::value(std::string option, Reader read) {
    declare(Declared::Kind::Value, std::move(option)).read = std::move(read);
}

int CommandLine::usage(const std::string& problem) const { return usageError(problem, m_command); }

std::optional<int> CommandLine::parse(const std::vector<std::string>& args) {
    // Help wins over everything else on the line, as it did before there was a parser.
    if (std::any_of(args.begin(), args.end(), [](const std::string& a) { return a == "--help" || a == "-h"; })) {
        std::fputs(m_help.c_str(), stdout);
        if (!m_help.empty() && m_help.back() != '\n')
            std::fputc('\n', stdout);
        return 0;
    }
    CLI::App app(m_help, m_command);
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
    return std::nullopt;
}

}  // namespace softtouch::cli
