// The registry rows the web preview can draw (src/relief/techniques/registry.cpp: shaderFile,
// shaderFunction, shaderSamplers {sampler, array, mipChain, fallback}) and the defaults of the
// parameters that reach ReliefParams (maxSteps: the row's IterationCap parameter, binarySteps,
// ascend). A GoogleTest (tests/web_page_test.cpp) checks every line against the registry, so
// nothing here drifts from the C++ side. One row per line.
export const kTechniques = {
    'linear': {file: 'linear.glsl', fn: 'reliefLinear', samplers: [['heights', '']], maxSteps: 32, binarySteps: 8},
    'parallax': {file: 'parallax.glsl', fn: 'reliefParallax', samplers: [['heights', '']], maxSteps: 0, binarySteps: 0},
    'cone': {file: 'cone.glsl', fn: 'reliefCone', samplers: [['heights', ''], ['cones', 'cones']], maxSteps: 4096, binarySteps: 0},
    'relaxed-cone': {file: 'relaxed_cone.glsl', fn: 'reliefRelaxedCone', samplers: [['heights', ''], ['cones', 'cones']], maxSteps: 15, binarySteps: 8},
    'maxmip': {file: 'maxmip.glsl', fn: 'reliefMaxmip', samplers: [['heights', ''], ['pyramid', 'level0', true]], maxSteps: 0, binarySteps: 0},
    'quadtree': {file: 'quadtree.glsl', fn: 'reliefQuadtree', samplers: [['heights', ''], ['pyramid', 'level0', true]], maxSteps: 0, binarySteps: 0},
    'qdm': {file: 'qdm.glsl', fn: 'reliefQdm', samplers: [['heights', ''], ['qdm', 'qdm']], maxSteps: 4096, binarySteps: 0},
    'safety-sd': {file: 'safety_sd.glsl', fn: 'reliefSafetySd', samplers: [['heights', ''], ['sd', 'sd']], maxSteps: 0, binarySteps: 0},
};
