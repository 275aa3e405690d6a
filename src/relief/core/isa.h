#pragma once
// The instruction set the CPU tracers run with, chosen once per process at run time.
// The binary stays portable (baseline x86-64): each technique's per-ray loop is compiled a second
// and third time with a target attribute (SSE4.2; AVX2+FMA+BMI2) and [[gnu::flatten]], so the
// whole inline walk is inlined into it and compiled for that target (std::floor becomes roundss,
// BMI shifts, VEX encoding). Out-of-line callees (Surface::clip, libm) stay baseline.
// Invariant: every ISA gives bit-identical hits. The build uses -ffp-contract=off (CMakeLists),
// so FMA is never contracted into an expression; only instruction selection differs.
// Choice: RELIEF_ISA=baseline|sse4|avx2|auto (the environment), else the best the CPU supports.
#include <relief/core/error.h>

#include <cstdint>
#include <span>
#include <string_view>

namespace relief {

enum class Isa : uint8_t { Baseline, Sse4, Avx2 };
inline constexpr Isa kAllIsas[] = {Isa::Baseline, Isa::Sse4, Isa::Avx2};

std::string_view toString(Isa isa);
// "baseline", "sse4", "avx2" or "auto" (the best supported); anything else is an error that
// names the choices, and so is an ISA this CPU lacks.
Result<Isa> parseIsa(std::string_view name);
bool isaSupported(Isa isa);
Isa bestSupportedIsa();

// The ISA the tracers use now: the last setTracerIsa, else RELIEF_ISA, else the best supported.
// A RELIEF_ISA that parseIsa refuses gives a warning on stderr at the first call and the best
// supported ISA (a library does not end its host); the CLI checks it first
// (checkIsaEnvironment) and refuses it as any other error (exit 1, or 5 for an ISA the CPU lacks).
Isa activeIsa();
std::string_view tracerIsa();  // toString(activeIsa())
Status checkIsaEnvironment();
// Switches the ISA for every tracer in the process (A/B runs, tests); an unsupported one is
// refused. Not meant to race a trace in progress (the next batch may use either).
Status setTracerIsa(Isa isa);

// Whether the rows that have a SIMD packet path (Highway: quadtree, maxmip, exact) take it: false
// when the environment sets RELIEF_PACKETS=0 (an A/B against their scalar paths); read once.
// ISA baseline takes the scalar paths too (the portable code as a whole).
bool packetsEnabled();

// Scoped switch for tests and benchmarks; restores the previous ISA.
class IsaOverride {
public:
    explicit IsaOverride(Isa isa) : m_previous(activeIsa()) { (void)setTracerIsa(isa); }
    ~IsaOverride() { (void)setTracerIsa(m_previous); }
    IsaOverride(const IsaOverride&) = delete;
    IsaOverride& operator=(const IsaOverride&) = delete;

private:
    Isa m_previous;
};

}  // namespace relief

// Target attributes of the dispatched loops (GCC and Clang; x86-64 only). Highway's target
// strings, without the AES/CLMUL the tracers do not use.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RELIEF_ISA_DISPATCH 1
#define RELIEF_TARGET_SSE4 __attribute__((target("sse2,ssse3,sse4.1,sse4.2"), flatten))
#define RELIEF_TARGET_AVX2 \
    __attribute__((target("sse2,ssse3,sse4.1,sse4.2,avx,avx2,bmi,bmi2,fma,f16c"), flatten))
#else
#define RELIEF_ISA_DISPATCH 0
#endif
