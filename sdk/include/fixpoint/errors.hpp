// Error types shared by the host and every plugin.
//
// Plugins throw plain messages; the host adds the `file:line:col: path:` prefix, because
// only the host knows where in the YAML a value came from.
#pragma once

#include <stdexcept>
#include <string>

namespace fp {

/// Base of every fixpoint error. `what()` is a one-line message for the user.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
    ~Error() override;
};

/// Bad input from the user (config, command line, data): exit code 2.
class InputError : public Error {
public:
    using Error::Error;
    ~InputError() override;
};

/// A parameter value a plugin refuses. `param` names the parameter as declared in the
/// plugin's schema (empty: the object as a whole); the host turns it into a YAML position.
class ParamError : public InputError {
public:
    ParamError(std::string param, const std::string& message)
        : InputError(message), param_(std::move(param)) {}
    explicit ParamError(const std::string& message) : InputError(message) {}
    ~ParamError() override;
    const std::string& param() const noexcept { return param_; }

private:
    std::string param_;
};

/// Something that should not happen whatever the input: exit code 1.
class InternalError : public Error {
public:
    using Error::Error;
    ~InternalError() override;
};

/// Thrown by the host when the user interrupts a render (Ctrl-C).
class Cancelled : public Error {
public:
    Cancelled() : Error("interrupted") {}
    ~Cancelled() override;
};

} // namespace fp
