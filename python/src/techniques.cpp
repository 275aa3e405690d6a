// relief.techniques(), relief.bake() and relief.Maps: the registry rows and baked maps.
#include <relief/techniques/registry.h>

#include "module.h"

namespace relief::python {

namespace {

py::dict paramDict(const ParamSpec& p) {
    py::dict d;
    d["name"] = std::string(p.name);
    d["default"] = p.defaultValue;
    d["min"] = p.minValue;
    d["max"] = p.maxValue;
    d["integer"] = p.integer;
    d["help"] = std::string(p.help);
    d["role"] = std::string(toString(p.role));
    return d;
}

py::list techniqueRows() {
    py::list rows;
    for (const TechniqueInfo& info : techniques()) {
        py::dict row;
        row["name"] = std::string(info.name);
        row["paper"] = std::string(info.paper);
        row["summary"] = std::string(info.summary);
        row["contract"] = std::string(toString(info.contract));
        row["reference"] = info.reference;
        row["has_maps"] = info.buildMaps != nullptr;
        row["gl"] = !info.glsl.empty();
        py::list params, variants;
        for (const ParamSpec& p : info.params) params.append(paramDict(p));
        for (const VariantSpec& v : info.variants) {
            py::dict d;
            d["label"] = std::string(v.label);
            d["params"] = std::string(v.params);
            d["contract"] = std::string(toString(v.contract));
            d["summary"] = std::string(v.summary);
            d["clamp_only"] = v.clampOnly;
            variants.append(d);
        }
        row["parameters"] = params;
        row["variants"] = variants;
        rows.append(row);
    }
    return rows;
}

PyMaps bake(const PyHeightfield& hf, const std::string& technique, const py::kwargs& params) {
    const TechniqueInfo* info = orRaise(lookupTechnique(technique));
    const Overrides overrides = overridesOf(params);
    auto surface = hf.surface();
    auto maps = std::make_shared<MapFile>();
    maps->source = mapSourceOf(*surface);
    maps->techniques.push_back(
        orRaise(withoutGil([&] { return bakeMaps(*info, surface, overrides); })));
    return PyMaps{std::move(maps), "maps baked by relief.bake(" + technique + ")"};
}

PyMaps loadMaps(const std::string& path, const PyHeightfield& hf) {
    auto file = orRaise(withoutGil([&] { return readMapFile(path); }));
    PyMaps maps{std::make_shared<const MapFile>(std::move(file)), path};
    maps.check(*hf.surface());
    return maps;
}

}  // namespace

void bindTechniques(py::module_& m) {
    using namespace pybind11::literals;
    m.def("techniques", &techniqueRows,
          "The registry rows, one dict each: name, paper, summary, contract (of the defaults), "
          "reference, has_maps, gl, parameters (name, default, min, max, integer, help, role) and "
          "variants (label, params, contract, summary, clamp_only).");
    m.def("bake", &bake, "heightfield"_a, "technique"_a,
          "Builds a technique's maps as `relief bake` does (parameters as keywords, snake_case or "
          "kebab-case names); ValueError for a row without maps or a parameter the maps do not "
          "record.");
    py::class_<PyMaps>(m, "Maps", "Baked maps of one heightfield (one or more techniques).")
        .def_static("load", &loadMaps, "path"_a, "heightfield"_a,
                    "Reads a map file (relief bake -o FILE.exr) and checks it against the "
                    "heightfield: ValueError for maps baked from another heightfield, size, edge "
                    "mode or depth, OSError when the file cannot be read.")
        .def(
            "save",
            [](const PyMaps& maps, const std::string& path) {
                orRaise(withoutGil([&] { return writeMapFile(path, *maps.file); }));
            },
            "path"_a, "Writes the maps as one OpenEXR file (what relief --maps FILE reads).")
        .def(
            "check", [](const PyMaps& maps, const PyHeightfield& hf) { maps.check(*hf.surface()); },
            "heightfield"_a, "ValueError when the maps were baked from another heightfield.")
        .def_property_readonly("techniques",
                               [](const PyMaps& maps) {
                                   py::list names;
                                   for (const TechniqueMaps& t : maps.file->techniques)
                                       names.append(t.technique);
                                   return names;
                               })
        .def_property_readonly(
            "parameters",
            [](const PyMaps& maps) {
                py::dict out;
                for (const TechniqueMaps& t : maps.file->techniques)
                    out[py::str(t.technique)] = t.parameters;
                return out;
            },
            "{technique: {parameter: value as baked}}")
        .def_property_readonly("source",
                               [](const PyMaps& maps) {
                                   const MapSource& s = maps.file->source;
                                   py::dict d;
                                   d["heightfield_hash"] = s.heightfieldHash;
                                   d["width"] = s.width;
                                   d["height"] = s.height;
                                   d["edge"] = s.edge;
                                   d["depth"] = s.depth;
                                   return d;
                               })
        .def_property_readonly(
            "arrays",
            [](py::object self) {
                const PyMaps& maps = self.cast<const PyMaps&>();
                py::dict out;
                for (const TechniqueMaps& t : maps.file->techniques)
                    for (const MapArray& a : t.arrays) {
                        // Read-only views (height, width, channels) that keep the maps alive.
                        const py::ssize_t c = a.channels, w = a.width, f = sizeof(float);
                        py::array_t<float> view({py::ssize_t(a.height), w, c},
                                                {w * c * f, c * f, f}, a.data.data(), self);
                        view.attr("setflags")(py::arg("write") = false);
                        out[py::str(t.technique + "/" + a.name)] = view;
                    }
                return out;
            },
            "{'technique/array': (height, width, channels) float32 read-only view}")
        .def("__repr__", [](const PyMaps& maps) {
            std::string names;
            for (const TechniqueMaps& t : maps.file->techniques)
                names += (names.empty() ? "" : ", ") + t.technique;
            return "relief.Maps(" + names + ")";
        });
}

}  // namespace relief::python
