// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The host programs' command lines on CLI11: help layout, --help/--version,
// the value checks and the one-line usage errors. See command_line.hpp.
#include "cellguard/host/command_line.hpp"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <utility>

#include "cellguard/host/cli.hpp"

namespace cellguard::host {
namespace {

/// The help text: "usage: <usage>", the description, the options by group
/// in the order they were added (an option as "--name VALUE_NAME", its
/// help beside it), the footer.
class HelpFormatter final : public CLI::Formatter {
public:
    explicit HelpFormatter(std::string usage) : usage_(std::move(usage)) { column_width(30U); }

    std::string make_help(const CLI::App* app, std::string /*name*/, CLI::AppFormatMode /*mode*/) const override {
        std::ostringstream out;
        out << "usage: " << usage_ << "\n";
        if (!app->get_description().empty()) {
            out << "\n" << app->get_description() << "\n";
        }
        for (const std::string& group : app->get_groups()) {
            const std::vector<const CLI::Option*> options = app->get_options(
                [&group](const CLI::Option* o) { return o->get_group() == group; });
            if (group.empty() || options.empty()) {
                continue;
            }
            out << "\n" << group << ":\n";
            for (const CLI::Option* o : options) {
                out << make_option(o, o->get_positional());
            }
        }
        if (!app->get_footer().empty()) {
            out << "\n" << app->get_footer() << "\n";
        }
        return out.str();
    }

    /// "-h, --help": an option's names separated by ", " (a negated flag's too, without CLI11's "{false}").
    std::string make_option_name(const CLI::Option* o, bool positional) const override {
        if (positional) {
            return o->get_name(true, false);
        }
        std::string names;
        for (const std::string& n : o->get_snames()) {
            names += (names.empty() ? "-" : ", -") + n;
        }
        for (const std::string& n : o->get_lnames()) {
            names += (names.empty() ? "--" : ", --") + n;
        }
        return names;
    }

    /// Only the value's name (option_text); the rules (needs, excludes) are in the help texts.
    std::string make_option_opts(const CLI::Option* o) const override {
        return o->get_option_text().empty() ? std::string() : " " + o->get_option_text();
    }

private:
    std::string usage_;
};

/// What a refused command line says, in this program's words where CLI11's
/// are not: a missing value ("--out: 1 required TEXT missing", the only
/// ArgumentMismatch options of one value per occurrence raise) is "--out
/// needs a value", like a value that is the next option.
std::string message_of(const CLI::ParseError& e) {
    std::string what = e.what();
    const std::string missing = " missing";
    const std::size_t colon = what.find(": ");
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && colon != std::string::npos &&
        what.size() > missing.size() && what.compare(what.size() - missing.size(), missing.size(), missing) == 0) {
        return what.substr(0U, colon) + " needs a value";
    }
    return what;
}

}  // namespace

void reject(const std::string& message) { throw CLI::ValidationError(message); }

bool parse_integer(const std::string& text, long lo, long hi, long& value) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || errno != 0 || end != text.c_str() + text.size() || v < lo || v > hi) {
        return false;
    }
    value = v;
    return true;
}

long integer_value(const std::string& name, const std::string& text, long lo, long hi) {
    long v = 0;
    if (!parse_integer(text, lo, hi, v)) {
        reject(name + " expects an integer " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'");
    }
    return v;
}

void OptionRef::needs(OptionRef other) const { option_->needs(other.option_); }

void OptionRef::excludes(OptionRef other) const { option_->excludes(other.option_); }

void OptionRef::required() const { option_->required(); }

std::size_t OptionRef::count() const { return option_->count(); }

CommandLine::CommandLine(std::string program, std::string usage, const std::string& description,
                         const std::string& footer)
    : program_(std::move(program)), app_(std::make_unique<CLI::App>(description, program_)) {
    app_->formatter(std::make_shared<HelpFormatter>(std::move(usage)));
    app_->footer(footer);
    app_->set_help_flag();  // replaced in parse() by one that answers where it stands
    app_->allow_extras();   // unknown arguments are reported by parse(), in this program's words
    app_->option_defaults()->group("options");
}

CommandLine::~CommandLine() = default;

void CommandLine::group(const std::string& name) { app_->option_defaults()->group(name); }

OptionRef CommandLine::value(const std::string& name, const std::string& value_name, const std::string& help,
                             Take take) {
    auto each = [name, take = std::move(take)](const std::vector<std::string>& values) {
        for (const std::string& v : values) {
            if (v.rfind("--", 0U) == 0U) {
                reject(name + " needs a value");
            }
            take(v);
        }
    };
    // One value per occurrence (allow_extra_args(false)); every occurrence kept, in order.
    return OptionRef(app_->add_option_function<std::vector<std::string>>(name, each, help)
                         ->allow_extra_args(false)
                         ->option_text(value_name));
}

OptionRef CommandLine::text(const std::string& name, std::string& target, const std::string& value_name,
                            const std::string& help) {
    return value(name, value_name, help, [&target](const std::string& v) { target = v; });
}

OptionRef CommandLine::integer(const std::string& name, int& target, long lo, long hi, const std::string& value_name,
                               const std::string& help) {
    return value(name, value_name, help, [&target, name, lo, hi](const std::string& v) {
        target = static_cast<int>(integer_value(name, v, lo, hi));
    });
}

OptionRef CommandLine::choice(const std::string& name, std::string& target, const std::vector<std::string>& allowed,
                              const std::string& help, bool value_optional) {
    CLI::Option* o = app_->add_option(name, target, help);
    if (value_optional) {
        o->expected(0, 1);
    }
    return OptionRef(o->check(CLI::IsMember(allowed)));
}

OptionRef CommandLine::flag(const std::string& names, bool& target, const std::string& help) {
    return OptionRef(app_->add_flag(names, target, help));
}

OptionRef CommandLine::argument(const std::string& name, const std::string& help, const Take& take, bool required) {
    CLI::Option* o = app_->add_option_function<std::string>(name, take, help)->group("arguments");
    return OptionRef(required ? o->required() : o);
}

int CommandLine::parse(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    if (app_->get_option_no_throw("--help") == nullptr) {
        // Listed last, in the current default group; answered as soon as parsed.
        app_->add_flag_callback(
                "-h,--help", [] { throw CLI::CallForHelp(); }, "print this help and exit")
            ->trigger_on_parse();
        app_->set_version_flag("--version", version_text(program_), "print the version and exit")->trigger_on_parse();
    }
    // An unknown argument is reported first: it is the likely cause of the other errors.
    auto refuse = [this, &err](const std::string& message) {
        const std::vector<std::string> unknown = app_->remaining();
        err << usage_error_line(program_, unknown.empty() ? message : "unknown argument '" + unknown.front() + "'")
            << std::flush;
        return kExitUsage;
    };
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes the last argument first
        app_->parse(reversed);
        return app_->remaining().empty() ? -1 : refuse("");
    } catch (const CLI::CallForHelp&) {
        out << app_->help() << std::flush;
        return 0;
    } catch (const CLI::CallForVersion& e) {
        out << e.what() << "\n" << std::flush;
        return 0;
    } catch (const CLI::ParseError& e) {
        return refuse(message_of(e));
    }
}

int CommandLine::parse(int argc, const char* const* argv) {
    std::vector<std::string> args;
    for (int i = 1; i < argc; ++i) {
        args.emplace_back(argv[i]);
    }
    return parse(args, std::cout, std::cerr);
}

}  // namespace cellguard::host
