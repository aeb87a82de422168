#pragma once
// The judge of docs/design.md §2's contract lives in the library (visibility/ExactJudge.h), where the
// bench uses it too; the tests name it as they always have.

#include "visibility/ExactJudge.h"

namespace sightline::test {

using sightline::ExactJudge;
using sightline::judgeTriangle;
using sightline::kTieMetres;
using sightline::RayKind;
using sightline::raysToJudge;
using sightline::toString;
using sightline::TriangleVerdict;
using sightline::Verdict;

} // namespace sightline::test
