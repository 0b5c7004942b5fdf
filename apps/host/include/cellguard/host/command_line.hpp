// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file command_line.hpp
/// The host programs' command lines on CLI11 (Debian libcli11-dev), set up
/// alike (cli.hpp says what every program does): `-h`/`--help` prints the
/// usage, generated from the options, to stdout and exits 0 (wherever it
/// stands, unless it is another option's value); `--version` prints
/// "<program> <version>" and exits 0; every usage error is one line on
/// stderr, "<program>: <message> (see --help)", and exit status 2:
/// - "<option> needs a value": an option given last without its value, or
///   followed by another option (a value never starts with "--");
/// - "<option> expects ..., got '<value>'": a value its take function refused
///   (reject());
/// - "unknown argument '<arg>'": anything no option or argument takes
///   (reported before the errors below, as their likely cause);
/// - CLI11's own words for the rules declared on the options:
///   "<option> is required", "<option> requires <option>" (needs),
///   "<option> excludes <option>".
/// Values are taken as text and checked by the program's take functions, so
/// that each message says what the option expects; a repeated option's
/// values are taken in order (the last one counts unless its take function
/// refuses a repeat).
/// CLI11 is an implementation detail: a program sees only this header (CLI11
/// in a translation unit cost 4.5 s of g++ and 17 s of clang-tidy CPU time,
/// 2026-12-06, and ten programs include this header).
#ifndef CELLGUARD_HOST_COMMAND_LINE_HPP
#define CELLGUARD_HOST_COMMAND_LINE_HPP

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace cellguard::host {

/// One option of a CommandLine, for the rules between options (valid as
/// long as its CommandLine). The rules are checked by CommandLine::parse().
class OptionRef {
public:
    /// The option @p option of a CommandLine (not null).
    explicit OptionRef(CLI::Option* option) noexcept : option_(option) {}

    /// Allowed only together with @p other: "<option> requires <other>".
    void needs(OptionRef other) const;
    /// Never together with @p other: "<option> excludes <other>".
    void excludes(OptionRef other) const;
    /// Must be given: "<option> is required".
    void required() const;
    /// How many times the option was given (after CommandLine::parse()).
    [[nodiscard]] std::size_t count() const;

private:
    CLI::Option* option_;
};

/// Refuses a value: throws the usage error @p message. For take functions.
[[noreturn]] void reject(const std::string& message);

/// @p text (decimal, the whole text) as an integer in [@p lo, @p hi] into
/// @p value; false for anything else.
bool parse_integer(const std::string& text, long lo, long hi, long& value);

/// parse_integer() of @p text, else reject(): "<name> expects an integer
/// LO..HI, got '<text>'".
long integer_value(const std::string& name, const std::string& text, long lo, long hi);

/// One program's command line.
class CommandLine {
public:
    /// What a value option or an argument does with its value (each
    /// occurrence, in command-line order); calls reject() to refuse it.
    using Take = std::function<void(const std::string& value)>;

    /// @p program: the name in messages and --version; @p usage: the usage
    /// line after "usage: "; @p description: the text under it; @p footer:
    /// the text after the options (the exit statuses).
    CommandLine(std::string program, std::string usage, const std::string& description, const std::string& footer);
    CommandLine(const CommandLine&) = delete;
    CommandLine& operator=(const CommandLine&) = delete;
    CommandLine(CommandLine&&) = delete;
    CommandLine& operator=(CommandLine&&) = delete;
    ~CommandLine();

    /// The options added from now on are listed under the heading @p name
    /// in the help (until the next group(); the first is "options").
    void group(const std::string& name);

    /// An option with a value, "--name VALUE" or "--name=VALUE", listed as
    /// "@p name @p value_name".
    OptionRef value(const std::string& name, const std::string& value_name, const std::string& help, Take take);
    /// value() that stores the text in @p target.
    OptionRef text(const std::string& name, std::string& target, const std::string& value_name,
                   const std::string& help);
    /// value() that stores an integer in [@p lo, @p hi] in @p target (integer_value()).
    OptionRef integer(const std::string& name, int& target, long lo, long hi, const std::string& value_name,
                      const std::string& help);
    /// An option whose value is one of @p allowed, stored in @p target
    /// (CLI11's words for another: "--name: Check ... failed"); with
    /// @p value_optional, "--name" alone is allowed and stores "" (which
    /// @p allowed must then hold).
    OptionRef choice(const std::string& name, std::string& target, const std::vector<std::string>& allowed,
                     const std::string& help, bool value_optional = false);
    /// A flag (@p names: "--name", or "--name,!--no-name" for a pair whose
    /// last one counts) that sets @p target.
    OptionRef flag(const std::string& names, bool& target, const std::string& help);
    /// A positional argument NAME (upper case), required unless @p required is false.
    OptionRef argument(const std::string& name, const std::string& help, const Take& take, bool required = true);

    /// Parses @p args (without the program name): -1 to run; else the exit
    /// status, after printing the usage or version to @p out (0) or the
    /// usage error to @p err (kExitUsage).
    int parse(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
    /// parse() of main()'s arguments, printing to stdout and stderr.
    int parse(int argc, const char* const* argv);

private:
    std::string program_;
    std::unique_ptr<CLI::App> app_;
};

}  // namespace cellguard::host

#endif  // CELLGUARD_HOST_COMMAND_LINE_HPP
