// Defaults of the sanitizer runtimes, compiled into every executable of a FIXPOINT_SANITIZE
// build (the top-level CMakeLists.txt adds this file), so that the tests, the CLI they run
// and the fuzz targets behave alike however they are started. ASAN_OPTIONS, UBSAN_OPTIONS
// and LSAN_OPTIONS given at run time still override these.

#define FIXPOINT_SANITIZER_HOOK extern "C" __attribute__((visibility("default"), used)) const char*

// detect_odr_violation=1 rather than 2: a test loads a renamed copy of the SDK library as a
// would-be plugin on purpose, which registers the same globals twice with the same sizes.
// A true ODR violation between the SDK and a plugin (a global of another size) is still
// reported.
FIXPOINT_SANITIZER_HOOK __asan_default_options() { return "detect_odr_violation=1"; }

// Where a finding comes from matters more than the shortest log.
FIXPOINT_SANITIZER_HOOK __ubsan_default_options() { return "print_stacktrace=1"; }

// Fontconfig's memory, allocated under cairo's font selection (the mfs renderer's captions:
// cairo_select_font_face -> FcPatternDuplicate, FcInitLoadConfigAndFonts), is never freed
// and reported as leaked at exit. Not ours: mfs destroys every cairo object it makes; only
// cairo_debug_reset_static_data() and FcFini() would free it.
FIXPOINT_SANITIZER_HOOK __lsan_default_suppressions() { return "leak:libfontconfig.so\nleak:libcairo.so\n"; }
