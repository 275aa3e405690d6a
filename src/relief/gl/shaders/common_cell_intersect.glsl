// Exact first hit of a ray segment with S inside one cell. Mirrors firstHitOnPlane and
// firstHitInCell of src/relief/surface/cell_intersect.h.

// Smallest t in [ta, tb] where the ray is on or below `plane`, or kInfinity.
float firstHitOnPlane(CellPlane plane, vec3 origin, vec3 direction, float cellX, float cellY,
                      float ta, float tb) {
    precise float ou = origin.x - cellX, ov = origin.y - cellY;
    precise float above0 =
        origin.z + ta * direction.z - at(plane, ou + ta * direction.x, ov + ta * direction.y);
    if (above0 <= 0.0) return ta;
    precise float above1 =
        origin.z + tb * direction.z - at(plane, ou + tb * direction.x, ov + tb * direction.y);
    if (above1 > 0.0) return kInfinity;
    precise float t = ta + (tb - ta) * divide(above0, above0 - above1);
    return t;
}

// Smallest t in [ta, tb] where the ray is on or below S in cell (ci, cj), or kInfinity.
float firstHitInCell(CellPlanes planes, Ray ray, int ci, int cj, float ta, float tb) {
    const float cellX = float(ci) + 0.5, cellY = float(cj) + 0.5;
    const float t0 =
        firstHitOnPlane(planes.first, ray.origin, ray.direction, cellX, cellY, ta, tb);
    if (t0 == ta) return t0;
    const float t1 =
        firstHitOnPlane(planes.second, ray.origin, ray.direction, cellX, cellY, ta, tb);
    return min(t0, t1);
}
