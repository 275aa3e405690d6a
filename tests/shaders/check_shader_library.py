#!/usr/bin/python3
"""Compiles one function of the engine shader library (shaders/relief/) for one target.

Writes a small fragment shader that includes common.glsl and the technique's file (and the files
they name on `// requires:` lines) and calls the function and its shadow query, then checks it
with glslangValidator: GLSL 3.30 core and GLSL ES 3.00 as they are, Vulkan GLSL 4.50 to SPIR-V,
from which spirv-cross must produce HLSL (shader model 5.0) that contains the function.
With --example DOC instead: the first ```glsl block of DOC that has a #version line, its
`// relief: a.glsl, b.glsl (...)` line replaced by those library files (docs/engine.md's shader).
Called by tests/shader_library_test.cpp; exit 0 when it compiles, 1 otherwise (the tools' output
on stderr).
"""
import argparse
import pathlib
import re
import subprocess
import sys

TARGETS = ("330", "300es", "vulkan")


def library_text(library: pathlib.Path, file: str) -> str:
    """common.glsl, then `file` after the files it requires, each once."""
    ordered = []

    def add(name):
        if name in ordered:
            return
        text = (library / name).read_text()
        for required in re.findall(r"^// requires: (\S+)$", text, re.M):
            add(required)
        ordered.append(name)

    add("common.glsl")
    add(file)
    return "".join(f"// ---- {name} ----\n{(library / name).read_text()}\n" for name in ordered)


def wrapper(target: str, library: str, function: str, samplers: list) -> str:
    vulkan = target == "vulkan"
    version = {"330": "#version 330 core", "300es": "#version 300 es", "vulkan": "#version 450"}
    lines = [version[target], library]
    location = (lambda k: f"layout(location = {k}) ") if vulkan else (lambda k: "")
    for k, name in enumerate(("vec2 vUv", "vec3 vViewDir", "vec3 vLightDir")):
        lines.append(f"{location(k)}in {name};")
    lines.append(f"{location(0)}out vec4 fragColor;")
    for k, name in enumerate(samplers):
        binding = f"layout(set = 0, binding = {k}) " if vulkan else ""
        lines.append(f"{binding}uniform sampler2D {name};")
    if vulkan:
        lines.append(f"layout(set = 0, binding = {len(samplers)}, std140) uniform ReliefBlock "
                     "{ ReliefParams params; } reliefBlock;")
        params = "reliefBlock.params"
    else:
        lines.append("uniform ReliefParams reliefUniforms;")
        params = "reliefUniforms"
    maps = ", ".join(samplers)
    lines += [
        "void main() {",
        f"    ReliefHit hit = {function}({maps}, vUv, vViewDir, {params});",
        f"    float lit = {function}Shadow({maps}, hit, vLightDir, {params});",
        "    fragColor = vec4(hit.uv, hit.depth, lit * float(hit.steps));",
        "}",
    ]
    return "\n".join(lines) + "\n"


def example_text(library: pathlib.Path, doc: pathlib.Path) -> str:
    for block in re.findall(r"```glsl\n(.*?)```", doc.read_text(), re.S):
        if not block.startswith("#version"):
            continue
        marker = re.search(r"^// relief: (.*?)(?: \(.*\))?$", block, re.M)
        if not marker:
            raise SystemExit(f"{doc}: the example has no '// relief: FILES' line")
        # common.glsl and the last file's requires come with it.
        last = marker.group(1).split(",")[-1].strip()
        return block[:marker.start()] + library_text(library, last) + block[marker.end():]
    raise SystemExit(f"{doc}: no ```glsl block with a #version line")


def run(command: list) -> bool:
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write(f"{' '.join(command)} failed ({result.returncode}):\n"
                         f"{result.stdout}{result.stderr}")
    return result.returncode == 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--library", required=True, type=pathlib.Path, help="shaders/relief")
    parser.add_argument("--file", help="technique file, e.g. cone.glsl")
    parser.add_argument("--function", help="e.g. reliefCone")
    parser.add_argument("--samplers", help="sampler names in order, comma-separated")
    parser.add_argument("--example", type=pathlib.Path, help="a doc whose example shader to compile")
    parser.add_argument("--target", required=True, choices=TARGETS)
    parser.add_argument("--out", required=True, type=pathlib.Path, help="a folder for the files")
    args = parser.parse_args()

    args.out.mkdir(parents=True, exist_ok=True)
    if args.example:
        source = args.out / "example.frag"
        source.write_text(example_text(args.library, args.example))
        return 0 if run(["glslangValidator", "-S", "frag", str(source)]) else 1
    if not (args.file and args.function and args.samplers):
        parser.error("--file, --function and --samplers are required without --example")
    stem = args.out / f"{args.function}-{args.target}"
    source = stem.with_suffix(".frag")
    source.write_text(wrapper(args.target, library_text(args.library, args.file), args.function,
                              args.samplers.split(",")))
    if args.target != "vulkan":
        return 0 if run(["glslangValidator", "-S", "frag", str(source)]) else 1
    spirv, hlsl = stem.with_suffix(".spv"), stem.with_suffix(".hlsl")
    if not run(["glslangValidator", "-V", "-S", "frag", "-o", str(spirv), str(source)]):
        return 1
    if not run(["spirv-cross", "--hlsl", "--shader-model", "50", str(spirv), "--output",
                str(hlsl)]):
        return 1
    text = hlsl.read_text() if hlsl.exists() else ""
    for name in (args.function, args.function + "Shadow"):
        if not re.search(rf"\b{name}\b", text):
            sys.stderr.write(f"{hlsl}: spirv-cross's HLSL has no function {name}\n")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
