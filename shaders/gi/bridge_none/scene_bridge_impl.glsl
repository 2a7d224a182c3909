// The scene bridge "none": the library sees only the screen. Nothing here is
// called (kSceneBridgeTraces is false and every caller checks it, so the
// compiler drops the branches); the functions exist so the shaders compile.
const bool kSceneBridgeTraces = false;

SceneHit sceneTraceClosest(vec3 origin, vec3 direction, float tMax) { return sceneMiss(); }
bool sceneTraceAny(vec3 origin, vec3 direction, float tMax) { return false; }
vec3 sceneDirectRadiance(SceneHit hit, vec3 toOrigin) { return vec3(0.0f); }
