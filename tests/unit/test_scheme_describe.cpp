// fp::scheme::describe (fixpoint/scheme.hpp): a scheme's parameters as the host sees them,
// `numbers` first whether the scheme lists it (the form written before describe) or not (the
// built-in schemes now, which declare no constructor). Building and stepping both forms is
// checked by the conformance suite: every built-in scheme is of the new form, its fixtures of
// broken schemes (tests/fixtures/) of the old.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/scheme.hpp>

#include <gtest/gtest.h>

#include <string_view>

namespace {

struct Implied final : fp::SchemeBase<Implied> {
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::seq("alpha", "0.5", "alpha_n"),
        fp::scheme::seq("a", "0.25", "a_n"),
    };

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        Buf<T> tp;
        c.t(tp, c.p);
        c.lin(c.p, identity - k["alpha"], c.p, k["a"], tp);
    }
};

class Listed final : public fp::SchemeBase<Listed> {
public:
    static constexpr fp::ParamSpec params[] = {
        fp::scheme::numbers_param,
        fp::scheme::seq("alpha", "0.5", "alpha_n"),
        fp::scheme::seq("a", "0.25", "a_n"),
    };
    using SchemeBase::SchemeBase;

    template <class T>
    void kernel(Chunk<T>& c, const Coefs& k, std::uint64_t) const {
        c.lin(c.p, identity - k["alpha"], c.p, k["a"], c.p);
    }
};

} // namespace

TEST(SchemeDescribe, NumbersComeFirstListedOrNot) {
    constexpr fp::PluginDescriptor implied = fp::scheme::describe<Implied>("implied", "a scheme");
    constexpr fp::PluginDescriptor listed = fp::scheme::describe<Listed>("listed", "a scheme");
    for (const fp::PluginDescriptor* d : {&implied, &listed}) {
        EXPECT_EQ(d->kind, fp::Kind::IterationScheme);
        ASSERT_EQ(d->n_params, 3u) << d->name;
        EXPECT_EQ(std::string_view(d->params[0].name), "numbers");
        EXPECT_EQ(d->params[0].type, fp::ParamType::Object);
        EXPECT_EQ(d->params[0].kind, fp::Kind::NumberSystem);
        EXPECT_EQ(std::string_view(d->params[0].default_yaml), "{type: real}");
        EXPECT_EQ(std::string_view(d->params[1].name), "alpha");
        EXPECT_EQ(std::string_view(d->params[2].name), "a");
        EXPECT_EQ(std::string_view(d->params[2].default_yaml), "0.25");
        EXPECT_NE(d->create, nullptr);
    }
    EXPECT_EQ(std::string_view(implied.name), "implied");
    EXPECT_EQ(std::string_view(implied.summary), "a scheme");
    // The coefficients are found by name among the scheme's own params, numbers not counted.
    static_assert(fp::scheme::detail::sequence_count(Implied::params) == 2);
    static_assert(fp::scheme::detail::sequence_count(Listed::params) == 2);
}
