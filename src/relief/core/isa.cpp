#include <relief/core/isa.h>

#include <atomic>
#if RELIEF_ISA_DISPATCH
#include <cpuid.h>
#endif
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace relief {
namespace {

// Set once from RELIEF_ISA or the CPU, then by setTracerIsa; read once per batch.
constexpr uint8_t kUnset = 0xff;
std::atomic<uint8_t> g_active{kUnset};

Result<Isa> isaFromEnvironment() {
    const char* value = std::getenv("RELIEF_ISA");
    if (value == nullptr || *value == '\0') return bestSupportedIsa();
    Result<Isa> isa = parseIsa(value);
    if (!isa) return Error{isa.error().kind, "RELIEF_ISA: " + isa.error().message};
    return isa;
}

#if RELIEF_ISA_DISPATCH
// F16C from CPUID leaf 1 (ECX bit 29): clang 14's __builtin_cpu_supports has no "f16c". The OS
// side (YMM state saved) is what __builtin_cpu_supports("avx") checks, which AVX2 needs anyway.
bool cpuHasF16c() {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    return __get_cpuid(1, &eax, &ebx, &ecx, &edx) != 0 && (ecx & bit_F16C) != 0;
}
#endif

}  // namespace

std::string_view toString(Isa isa) {
    switch (isa) {
        case Isa::Baseline: return "baseline";
        case Isa::Sse4: return "sse4";
        case Isa::Avx2: return "avx2";
    }
    return "?";
}

bool isaSupported(Isa isa) {
#if RELIEF_ISA_DISPATCH
    // libgcc's (and compiler-rt's) CPU model checks XCR0 too: AVX only where the OS saves YMM.
    __builtin_cpu_init();
    switch (isa) {
        case Isa::Baseline: return true;
        case Isa::Sse4:
            return __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("sse4.1") &&
                   __builtin_cpu_supports("sse4.2");
        case Isa::Avx2:
            return isaSupported(Isa::Sse4) && __builtin_cpu_supports("avx") &&
                   __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") &&
                   __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("fma") &&
                   cpuHasF16c();
    }
    return false;
#else
    return isa == Isa::Baseline;
#endif
}

Isa bestSupportedIsa() {
    for (Isa isa : {Isa::Avx2, Isa::Sse4})
        if (isaSupported(isa)) return isa;
    return Isa::Baseline;
}

Result<Isa> parseIsa(std::string_view name) {
    if (name == "auto") return bestSupportedIsa();
    for (Isa isa : kAllIsas)
        if (name == toString(isa)) {
            if (!isaSupported(isa))
                return makeError(ErrorKind::Unsupported, "this CPU lacks ISA '{}' (best: {})",
                                 name, toString(bestSupportedIsa()));
            return isa;
        }
    return makeError(ErrorKind::BadArgument,
                     "unknown ISA '{}' (choose baseline, sse4, avx2 or auto)", name);
}

Status checkIsaEnvironment() {
    Result<Isa> isa = isaFromEnvironment();
    if (!isa) return isa.error();
    return {};
}

Isa activeIsa() {
    uint8_t value = g_active.load(std::memory_order_relaxed);
    if (value == kUnset) {
        // The CLI refuses a bad RELIEF_ISA before any work (checkIsaEnvironment, exit 1 or 5);
        // a library user (the Python module, a C++ consumer) is warned once and gets the CPU's
        // best: a library never ends its host process over an environment variable.
        Result<Isa> isa = isaFromEnvironment();
        if (!isa)
            std::fprintf(stderr, "relief: warning: %s; using %s\n", isa.error().message.c_str(),
                         std::string(toString(bestSupportedIsa())).c_str());
        uint8_t expected = kUnset;
        g_active.compare_exchange_strong(expected, uint8_t(isa ? *isa : bestSupportedIsa()));
        value = g_active.load(std::memory_order_relaxed);
    }
    return Isa(value);
}

std::string_view tracerIsa() { return toString(activeIsa()); }

Status setTracerIsa(Isa isa) {
    if (!isaSupported(isa))
        return makeError(ErrorKind::Unsupported, "this CPU lacks ISA '{}'", toString(isa));
    g_active.store(uint8_t(isa), std::memory_order_relaxed);
    return {};
}

bool packetsEnabled() {
    static const bool enabled = [] {
        const char* value = std::getenv("RELIEF_PACKETS");
        return value == nullptr || std::string_view(value) != "0";
    }();
    return enabled;
}

}  // namespace relief
