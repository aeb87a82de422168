// HeckbertHerfSampler.cpp: every fragment of a triangle between the source sample and the receiver
// grid adds one to its receiver sample's count (additive blending).
#version 450 core
layout(location = 0) out float oCount;
void main() { oCount = 1.0; }
