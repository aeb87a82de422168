#pragma once
// The disagreement view's work, off the GUI thread: for the live exact answer of a pair, the same
// pair answered by a fast or coarse mode (project/Approximation.h) and every ray they answer
// differently sorted by the exact judge (visibility/RayDisagreement.h). One worker thread
// (LatestRequestWorker.h: the latest request wins) keeps the approximation's scene and samplers
// between requests (decimating a dense mesh once, not per drag frame) and, for the GL modes, a
// headless context of its own (OSMesa), so the view's context is never borrowed. Plain C++.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "editor/LatestRequestWorker.h"
#include "project/Approximation.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/Patch.h"
#include "visibility/RayDisagreement.h"
#include "visibility/ReceiverHeights.h"
#include "visibility/Scene.h"

namespace sightline::ui {

struct DisagreementRequest {
    std::uint64_t generation = 0;
    Approximation approximation;
    /// The level the exact answer sampled (its approximate scene is rebuilt when the pointer or
    /// the approximation changes).
    std::shared_ptr<const Scene> scene;
    Patch source, receiver;
    std::shared_ptr<const ReceiverHeights> heights;   ///< null: a flat receiver
    std::shared_ptr<const HiddenSampleMap> exact;     ///< the live exact answer for this pair
};

struct DisagreementAnswer {
    std::string error;   ///< empty: `disagreement` holds the answer
    std::shared_ptr<const RayDisagreement> disagreement;
    Approximation approximation;
    Patch source, receiver;
    std::size_t trianglesExact = 0, trianglesApproximate = 0;
    double prepareMs = 0.0;       ///< building the approximate scene (0 when kept from before)
    double approximateMs = 0.0;   ///< sampling the pair the approximate way
    double judgeMs = 0.0;
};

/// One line for the status bar: what the approximation gets wrong, each way, in the view's colours.
std::string disagreementStatus(const DisagreementAnswer& answer);

class DisagreementWorker {
public:
    /// Called on the worker thread with the request's generation and its answer.
    using Deliver = std::function<void(std::uint64_t generation, DisagreementAnswer answer)>;

    explicit DisagreementWorker(Deliver deliver);
    /// Waits for the request being worked on, drops any waiting one.
    ~DisagreementWorker();
    DisagreementWorker(const DisagreementWorker&) = delete;
    DisagreementWorker& operator=(const DisagreementWorker&) = delete;

    void request(DisagreementRequest request);

private:
    class State;   ///< the approximate sampler and the GL context, touched on the worker only
    std::shared_ptr<State> state_;
    LatestRequestWorker<DisagreementRequest, DisagreementAnswer> worker_;   // last: its thread uses state_
};

} // namespace sightline::ui
