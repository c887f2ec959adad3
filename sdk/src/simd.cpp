// fp::simd: names of Highway's targets and the process-wide pin (see fixpoint/simd.hpp).
#include <fixpoint/simd.hpp>

#include <hwy/highway.h>
#include <hwy/targets.h>

#include <cctype>
#include <cstdint>

namespace fp::simd {
namespace {

// The targets compiled into this library (HWY_TARGETS of this translation unit: plugins are
// built with the same flags) that the CPU has, as Highway's bits (a lower bit is better).
std::int64_t available() { return hwy::SupportedTargets() & HWY_TARGETS; }

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
    for (std::int64_t t = available(); t != 0; t &= t - 1) out.emplace_back(hwy::TargetName(t & -t));
    return out;
}

bool force_target(std::string_view name) {
    if (name.empty() || same_name(name, "best")) {
        hwy::SetSupportedTargetsForTest(0);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        return true;
    }
    hwy::SetSupportedTargetsForTest(0); // the real set, to look the name up in
    for (std::int64_t t = available(); t != 0; t &= t - 1) {
        const std::int64_t bit = t & -t;
        if (!same_name(name, hwy::TargetName(bit))) continue;
        hwy::SetSupportedTargetsForTest(bit);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        return true;
    }
    return false;
}

} // namespace fp::simd
