// The fuzz targets' one rule for an input's outcome: fp::InputError (a ParamError too) is the
// answer a user gets for bad input (exit code 2), and fine; anything else escaping is what the
// CLI would report as an internal error (exit code 1), so it is a finding: printed, then
// abort(), which makes libFuzzer keep the input.
#pragma once

#include <fixpoint/errors.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>

namespace fp::fuzz {

/// Printed as "TARGET: WHAT escaped ...: MESSAGE", then abort().
[[noreturn]] inline void finding(const char* target, const char* what, const char* message) {
    std::fprintf(stderr, "%s: %s escaped: %s\n", target, what, message);
    std::fflush(stderr);
    std::abort();
}

/// Runs `body` on one input with the rule above.
template <class Body>
void verdict(const char* target, Body&& body) {
    try {
        body();
    } catch (const fp::InputError&) {
        // Refused with a message: the expected outcome for most inputs.
    } catch (const fp::InternalError& e) {
        finding(target, "fp::InternalError", e.what());
    } catch (const fp::Error& e) {
        finding(target, "fp::Error", e.what());
    } catch (const std::exception& e) {
        finding(target, "std::exception", e.what());
    } catch (...) {
        finding(target, "an unknown exception", "(not a std::exception)");
    }
}

} // namespace fp::fuzz
