// The thesis's progressive cutter (SPEC R14-R17): scalpel contacts become cut points joined by mesh
// edges, each new point opening the one before it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hapticut/cutting/cut_model.h"

namespace hapticut::cutting {

struct CutterParams {
    /// A new point this close to an existing vertex (as a fraction of the local edge length) reuses it,
    /// so cutting never makes a sliver.
    double snapFraction = 0.2;
    /// A split that would make a triangle with a smaller angle than this snaps to a vertex instead.
    double minAngle_deg = 10;
    /// A fast stroke may cross many faces in one step; more crossings than this in one call stop there.
    int maxCrossingsPerCall = 256;
    /// Opening a cut point (R17): springs there shortened by this fraction (the thesis's 10%)...
    double shorten = 0.1;
    /// ...and the lips' anchors moved apart, each by this fraction of the local edge length, so the
    /// wound gapes against the stiff positioning springs (see CutModel::openCut).
    double retract = 0.3;
    /// Each opened point's gap closed with walls down to a floor inside the organ (CutModel::closeOpening),
    /// this many local edge lengths deep, so a closed organ stays closed and the tool meets the wound's
    /// walls instead of falling through it. Without walls a wound is a hole in the surface.
    /// A blade deeper than that (cutAt's depth) takes the floor down with it, up to maxWallDepthPerEdge
    /// times the shorter of the cut's two edges there (or their geometric mean, if more), which keeps
    /// the walls' triangles from slivers.
    bool walls = true;
    double wallDepthPerEdge = 1.0;
    double maxWallDepthPerEdge = 3.0;
};

struct CutStats {
    long cutPoints = 0, verticesAdded = 0, facesAdded = 0, cuts = 0;
    long joins = 0;          // cuts that ran into an open boundary or an earlier wound and joined it
    long woundsCrossed = 0;  // earlier wounds a cut went through, cutting their walls down to the floor
    double length_m = 0;     // along the cut, on the rest shape
    long openings = 0;       // cut points opened (R17)
    long wallsClosed = 0;    // openings closed with walls (CutterParams::walls)
    bool opened = false;     // true once any cut point has opened
};

class ProgressiveCutter {
public:
    ProgressiveCutter(CutModel& model, CutterParams params = {});

    /// The scalpel presses past its threshold at `bary` on `face`: starts a cut there, or continues the
    /// current one up to that point. `depth_m`: how deep the blade is under the rest surface there, which
    /// the walls of the points it opens reach down to. Returns true when the mesh changed. Debug builds
    /// (and builds with HAPTICUT_ASSERTS) check every cutting invariant after each change and stop at the
    /// first broken one.
    bool cutAt(std::uint32_t face, const Vec3& bary, double depth_m = 0);
    /// Where the blade is, seen from the cut: the point of the rest surface nearest to `device_m` among
    /// the organ's own faces (not the walls) a few rings round the last cut point, and how deep the device is under it
    /// (negative: above the surface). Only while cutting.
    struct BladeProjection {
        std::uint32_t face = 0;
        Vec3 bary = Vec3::Zero();
        double depth_m = 0;
        Vec3 normal = Vec3::UnitZ();  // the rest face's, outward
    };
    /// With the blade's `axis` (from its tip toward the handle), the point where the blade's line passes
    /// through those faces instead, when it does within them; else the nearest point.
    std::optional<BladeProjection> projectBlade(const Vec3& device_m, const Vec3& axis = Vec3::Zero());
    /// How far along its axis the blade's line is followed to the surface, either way from the tip.
    static constexpr double kBladeReach_m = 0.03;

    /// The force dropped below the threshold or contact was lost: the next cutAt starts a new cut.
    void endCut() { points_.clear(), lipVertices_.clear(), crossedFloor_.reset(); }

    bool cutting() const { return !points_.empty(); }
    /// Whether every opening so far was closed with walls: then a closed organ is still closed.
    bool woundsClosed() const { return stats_.wallsClosed == stats_.openings; }
    const std::vector<std::uint32_t>& points() const { return points_; }
    const CutStats& stats() const { return stats_; }

private:
    bool cutAtUnchecked(std::uint32_t face, const Vec3& bary);
    /// The blade seen at `bary` on `face`: the surface's normal there and the device's depth under it.
    BladeProjection projection(std::uint32_t face, const Vec3& bary, const Vec3& device_m) const;
    /// How many of this cut's latest points and their opened copies lie behind the blade: the cut neither
    /// follows the blade onto their faces nor joins them, though it may join its own older lips.
    static constexpr std::size_t kRecentLips = 16;
    bool recentLip(std::uint32_t v) const;
    /// The face around `vertex` that contains the rest point q, if any.
    bool fanContains(std::uint32_t vertex, const Vec3& q) const;
    /// Adds the next cut point toward q across the fan of the last one; false when there is none.
    bool crossToward(const Vec3& q);
    /// The neighbour of the last point, over the organ's surface and not yet in the cut, whose edge
    /// leads most nearly toward q, within kMostAskewStep of the way.
    std::optional<std::uint32_t> neighbourToward(const Vec3& q) const;
    static constexpr double kMostAskewStep = 0.25;  // the cosine of 75 degrees
    /// Over how many of its latest points a cut's way is taken, when it asks whether the blade is ahead.
    static constexpr std::size_t kWayPoints = 8;
    /// The same neighbour nearest q, whichever way its edge leads: the way out of a folded fan.
    std::optional<std::uint32_t> neighbourNearest(const Vec3& q) const;
    /// Each neighbour of the last point over the organ's surface (not across a rim or a wall) and not yet
    /// among the cut's points and lips, as often as its faces list it.
    template <class Visit>
    void forEachNeighbourOnTheSurface(Visit&& visit) const;
    /// The cut's point on edge (a, b) at a + u (b - a): a new vertex, or an end of the edge when the
    /// split would be too close to it or make a sliver.
    std::uint32_t pointOnEdge(std::uint32_t a, std::uint32_t b, double u);
    /// A new point on edge (a, b) near a + u (b - a) but clear of its end `avoid`, if the faces there allow
    /// a split no worse than they are.
    std::optional<std::uint32_t> splitAwayFrom(std::uint32_t a, std::uint32_t b, double u, std::uint32_t avoid);
    /// Goes on to `next`: a new point, a join when it lies on a boundary, or a slide along the boundary
    /// when the cut is only its start there. False, and nothing done, where `next` is no way on: the far
    /// lip of the wound this cut has just crossed.
    bool advanceTo(std::uint32_t next);
    /// Within the snap distance of a boundary edge opposite the last point, runs on to it and joins it.
    bool reachBoundary(const Vec3& q);
    void addPoint(std::uint32_t vertex);
    /// The cut reached `vertex` on an open boundary or an earlier wound's lip: it opens up to it, the
    /// wounds become one opening there (CutModel::separateFans), and this cut ends.
    void joinAt(std::uint32_t vertex);
    /// On an open end of the organ or the lip of a wound (CutModel::onRim): a cut stops there and joins
    /// what it ran into, unless it can cross the wound (crossingAt).
    bool onBoundary(std::uint32_t vertex) const;
    /// The way through an earlier wound from `lip`, a vertex on its lip: down the wall to the floor
    /// vertex under it, and up the far wall to the lip vertex nearest it across the gap.
    struct WoundCrossing {
        std::uint32_t floor, farLip;
    };
    std::optional<WoundCrossing> crossingAt(std::uint32_t lip) const;
    /// The floor vertex under a wound's lip vertex, if it has one.
    std::optional<std::uint32_t> floorBeside(std::uint32_t lip) const;
    /// Cuts the near wall from `lip` down to the floor and goes on from the floor up the far wall.
    void crossWound(std::uint32_t lip, const WoundCrossing& crossing);
    /// Whether `lip` is a lip of the stretch of wound this cut has just crossed: met again on the far
    /// side (a wound cut along a rough mesh's edges zigzags), it is never crossed back.
    bool justCrossed(std::uint32_t lip) const;
    /// How far along the wound's floor from where this cut crossed it that stretch reaches.
    static constexpr int kSameCrossingFloorHops = 6;
    /// Whether floor vertex `to` lies within `hops` edges of floor vertex `from` along a wound's floor.
    bool alongFloorWithin(std::uint32_t from, std::uint32_t to, int hops) const;
    /// Up to how many points a cut that turned back toward its start goes on from its first point.
    static constexpr std::size_t kTurnedBackCutPoints = 4;

    CutModel& model_;
    CutterParams params_;
    std::vector<std::uint32_t> points_;
    std::vector<std::uint32_t> lipVertices_;     // the current cut's points and their opened copies
    std::optional<std::uint32_t> crossedFloor_;  // where the current cut last crossed a wound
    CutStats stats_;
    double expectedMass_kg_ = 0;  // cutting conserves the organ's mass exactly
    bool wholeAtStart_ = true;    // with asserts: every invariant held before the first cut (else an unrepaired import)
    std::vector<std::uint32_t> nearbyFaces_, ring_;  // scratch for projectBlade
    struct Crossing {                                // an edge the way to the blade crosses
        double along;                                // where, as a fraction of the way
        std::uint32_t a, b;
        double u;
    };
    std::vector<Crossing> crossings_;  // scratch for crossToward
    double bladeDepth_m_ = 0;          // the latest cutAt's
};

}  // namespace hapticut::cutting
