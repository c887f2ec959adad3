// fp::simd: names of Highway's targets and the process-wide pin (see fixpoint/simd.hpp).
#include <fixpoint/simd.hpp>

#include <hwy/highway.h>
#include <hwy/targets.h>

#include <cctype>
#include <cstdint>

namespace fp::simd {
namespace {

// The targets compiled into this library (HWY_TARGETS of this translation unit: plugins are
// built with the same flags) that dispatch may use now, as Highway's bits (a lower bit is
// better): the CPU's, or the one force_target pinned.
std::int64_t available() { return hwy::SupportedTargets() & HWY_TARGETS; }

// The same for the CPU whatever is pinned, read once before any pin: force_target narrows
// hwy::SupportedTargets() to the target it pins, and calls this first. (Read live, the list
// shrank to the pinned target, and loops over every target that forced each in turn saw the
// last one only from their second pass on.)
std::int64_t cpu_targets() {
    static const std::int64_t t = hwy::SupportedTargets() & HWY_TARGETS;
    return t;
}

bool same_name(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

} // namespace

std::string active_target() {
    const std::int64_t t = available();
    return t ? hwy::TargetName(t & -t) : "none";
}

std::vector<std::string> supported_targets() {
    std::vector<std::string> out;
    for (std::int64_t t = cpu_targets(); t != 0; t &= t - 1) out.emplace_back(hwy::TargetName(t & -t));
    return out;
}

bool force_target(std::string_view name) {
    const std::int64_t cpu = cpu_targets(); // (first: see there)
    if (name.empty() || same_name(name, "best")) {
        hwy::SetSupportedTargetsForTest(0);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        return true;
    }
    for (std::int64_t t = cpu; t != 0; t &= t - 1) {
        const std::int64_t bit = t & -t;
        if (!same_name(name, hwy::TargetName(bit))) continue;
        hwy::SetSupportedTargetsForTest(bit);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        return true;
    }
    return false;
}

} // namespace fp::simd
