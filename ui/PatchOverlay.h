#pragma once
// What the editor paints on a patch (Eisemann & Décoret §9, "assisted visibility edition": the
// importance maps shown where they apply, so the designer sees which part of a doorway matters):
//   - receiver importance: per receiver sample, the fraction of source samples it sees;
//   - source importance: per source sample, the fraction of receiver samples that see it;
//   - light on the receiver: the soft shadow of the source as an area light (§8), white or the
//     project's colour-textured "light".
// Importance is shown for the current frame, or accumulated over the frames of a drag ("Accumulate
// While Editing") or of the project's animation (§9: "accumulation over time ... allows to
// investigate the impact of moving objects"), as a mean, maximum or ever-visible flag.
//
// A plain model, no GL and no widgets: the viewport feeds it each live result and uploads its
// texels; the window reads captions and read-outs from it; tests call it directly. With the
// overlay off and accumulation off, a live result costs nothing here (the interaction benchmark
// must not pay for a feature that is not shown).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <QString>

#include "editor/LiveVisibility.h"
#include "editor/ObjectEdits.h"
#include "editor/OverlayTexels.h"
#include "lighting/AreaLight.h"
#include "lighting/SoftShadow.h"
#include "project/Project.h"
#include "visibility/ImportanceMap.h"

namespace sightline::ui {

enum class OverlayKind { None, ReceiverImportance, SourceImportance, LightOnReceiver };

/// "none", "receiver", "source", "light" (`sightline --screenshot --overlay`); throws sightline::Error.
OverlayKind parseOverlayKind(std::string_view name);
const char* toString(OverlayKind kind);
/// The patch an overlay is drawn on (ObjectKind::None for OverlayKind::None).
ObjectKind overlayPatch(OverlayKind kind);
bool isImportance(OverlayKind kind);

/// "mean of 37 frames", "maximum of 37 animation frames", "ever visible in 2 frames", "this frame".
QString statisticPhrase(ImportanceStatistic statistic, int frames, bool animation, bool recordedPath = false);

class PatchOverlay {
public:
    void setKind(OverlayKind kind);
    OverlayKind kind() const { return kind_; }
    void setStatistic(ImportanceStatistic statistic);
    ImportanceStatistic statistic() const { return statistic_; }
    /// While on, every new live result adds a frame to both sides' accumulators. Turning it off
    /// pauses (the overlay shows the current frame); on again continues. An empty accumulation
    /// starts with the current frame.
    void setAccumulating(bool on);
    bool accumulating() const { return accumulating_; }

    /// A live result of `project`'s patches. `newFrame` false: the same result again, only to fill
    /// in what the overlay now needs (see needsLive()). Resets the accumulation when a sample grid
    /// changed. Returns at once when nothing is shown or accumulated.
    void setLive(const VisibilityResult& live, const Project& project, bool newFrame);
    /// The overlay needs setLive() with the current result (a kind switched on, a reset while
    /// accumulating, the light to reload).
    bool needsLive() const;

    /// Forgets every accumulated frame (the next live result starts a new accumulation).
    void resetAccumulation();
    /// A new document: forgets frames, the animation result and the light.
    void clear();
    /// An accumulation over the project's animation for one side: shown for that side's overlay
    /// (with the chosen statistic) until dropAnimationResult(), resetAccumulation() or clear().
    /// `recordedPath`: the frames were the project's recorded path's ("mean of 312 recorded-path frames").
    void showAnimationResult(ImportanceSide side, ImportanceAccumulator accumulator, bool recordedPath = false);
    /// The document changed: the animation result no longer describes it.
    void dropAnimationResult();
    bool hasAnimationResult() const { return animation_.has_value(); }

    /// Frames behind the importance shown (1 for the current frame; 0 when nothing is shown).
    int frames() const;
    /// The importance shown (importance kinds), or null.
    const ImportanceMap* importance() const { return shown_.values.empty() ? nullptr : &shown_; }
    /// The light shown (light kind), or null.
    const LightImage* light() const { return light_.rgb.empty() ? nullptr : &light_; }
    /// Why the light overlay is empty (the project's light failed to load); empty otherwise.
    const std::string& error() const { return error_; }

    /// The colours to draw, empty when nothing is shown. Changes exactly when version() does.
    const OverlayTexels& texels() const { return texels_; }
    std::uint64_t version() const { return version_; }

    /// "fraction of the source seen — mean of 37 frames" (importance kinds; empty otherwise).
    QString legendCaption() const;
    /// "receiver sample (12, 30): 43.2% of the source seen (mean of 37 frames)"; empty when
    /// nothing is shown or (a, b) is outside the grid.
    QString readOut(int a, int b) const;

private:
    struct AnimationResult {
        ImportanceSide side;
        ImportanceAccumulator accumulator;
        bool recordedPath = false;
    };
    struct Grids {
        int sourceNa = 0, sourceNb = 0, receiverNa = 0, receiverNb = 0;
        bool operator==(const Grids&) const = default;
    };

    const ImportanceAccumulator& accumulator(ImportanceSide side) const;
    /// Recomputes shown_/light_ and the texels from the current frame and the accumulations.
    void refresh();

    OverlayKind kind_ = OverlayKind::None;
    ImportanceStatistic statistic_ = ImportanceStatistic::Mean;
    bool accumulating_ = false;

    // The current frame, computed only for what is shown or accumulated: `fresh_` says which
    // of the three were computed from the last live result.
    struct Fresh {
        bool receiver = false, source = false, light = false;
    };
    Fresh fresh_;
    ImportanceMap currentReceiver_, currentSource_;
    LightImage currentLight_;
    std::optional<Grids> grids_;   ///< of the last live result
    ImportanceAccumulator receiverFrames_, sourceFrames_;
    bool seedPending_ = false;     ///< the accumulation should start with the current frame
    std::optional<AnimationResult> animation_;

    // The project's light for the current source grid (reloaded on clear() and grid changes).
    std::optional<AreaLight> areaLight_;
    std::string error_;

    // What is shown.
    ImportanceMap shown_;
    int shownFrames_ = 0;
    bool shownAccumulated_ = false;   ///< an accumulation (live or animation), not the current frame
    bool shownIsAnimation_ = false;
    bool shownIsPath_ = false;   ///< the animation result shown came from the recorded path
    LightImage light_;
    OverlayTexels texels_;
    std::uint64_t version_ = 0;
};

} // namespace sightline::ui
