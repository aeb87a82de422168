// RayLayer.cpp: the layer counts rays; n rays of opacity a cover 1 - (1 - a)^n of a pixel.
#version 450 core
layout(binding = 0) uniform sampler2D counts;
uniform vec2 frameSize;
uniform vec3 freeColour, blockedColour;
uniform vec2 log2Clear;   // log2(1 - a) of a free ray, of a blocked ray
layout(location = 0) out vec4 colour;
void main() {
    vec2 n = texture(counts, gl_FragCoord.xy / frameSize).rg;   // an R32F layer reads 0 blocked rays
    vec2 c = 1.0 - exp2(n * log2Clear);
    // Premultiplied: the free rays over the blocked ones.
    colour = vec4(freeColour * c.r + blockedColour * c.g * (1.0 - c.r), c.r + c.g * (1.0 - c.r));
}
