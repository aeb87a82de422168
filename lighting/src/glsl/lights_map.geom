// GlDirectLight.cpp: each triangle to every octant face it may enter (a face's octant is entered
// only if, on each axis, some corner lies on its side), clipped to the octant by s.q >= 0,
// projected as (q.x, q.y) / w on the upper faces and folded out as
// (s.x (w - s.y q.y), s.y (w - s.x q.x)) / w on the lower ones, w = s.q = |q|_1: linear in clip
// space, so rasterised exactly.
layout(triangles) in;
layout(triangle_strip, max_vertices = 24) out;
in vec3 world[];
flat in int instance[];
out vec3 toPoint;
out gl_PerVertex { vec4 gl_Position; float gl_ClipDistance[3]; };
uniform float invRadius;
void main()
{
    Emitter em = emitters[batch[instance[0]]];
    if (int(em.position.w) == kDirectional) {
        vec3 u, v;
        orthoBasis(em.direction.xyz, u, v);
        for (int i = 0; i < 3; ++i) {
            vec3 p = world[i];
            gl_Position = vec4(dot(p, u) * invRadius, dot(p, v) * invRadius, 0.0, 1.0);
            gl_ClipDistance[0] = gl_ClipDistance[1] = gl_ClipDistance[2] = 1.0;
            gl_Layer = instance[0];
            toPoint = vec3(dot(p, em.direction.xyz), 0.0, 0.0);
            EmitVertex();
        }
        EndPrimitive();
        return;
    }
    vec3 q[3] = vec3[3](world[0] - em.position.xyz, world[1] - em.position.xyz, world[2] - em.position.xyz);
    // A light with a range lights nothing past it, so a triangle whose box lies beyond it can
    // shadow nothing it lights.
    if (em.params.y > 0.0) {
        vec3 lo = min(min(q[0], q[1]), q[2]), hi = max(max(q[0], q[1]), q[2]);
        if (length(clamp(vec3(0.0), lo, hi)) > em.params.y)
            return;
    }
    for (int o = 0; o < 8; ++o) {
        vec3 s = vec3((o & 1) != 0 ? -1.0 : 1.0, (o & 2) != 0 ? -1.0 : 1.0, (o & 4) != 0 ? -1.0 : 1.0);
        vec3 reach = max(max(s * q[0], s * q[1]), s * q[2]);
        if (reach.x < 0.0 || reach.y < 0.0 || reach.z < 0.0)
            continue;
        for (int i = 0; i < 3; ++i) {
            float w = dot(s, q[i]);
            gl_Position = s.z > 0.0 ? vec4(q[i].x, q[i].y, 0.0, w)
                                    : vec4(s.x * (w - s.y * q[i].y), s.y * (w - s.x * q[i].x), 0.0, w);
            gl_ClipDistance[0] = s.x * q[i].x;
            gl_ClipDistance[1] = s.y * q[i].y;
            gl_ClipDistance[2] = s.z * q[i].z;
            gl_Layer = instance[0];
            toPoint = q[i];
            EmitVertex();
        }
        EndPrimitive();
    }
}
