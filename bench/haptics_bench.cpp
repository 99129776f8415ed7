// Google Benchmark: BVH build and refit, and one proxy update pressed into the heart and sliding, at
// several heart sizes.
#include <benchmark/benchmark.h>

#include <map>

#include "hapticut/collision/bvh.h"
#include "hapticut/haptics/proxy.h"
#include "hapticut/mesh/vertex_faces.h"
#include "hapticut/scene/bench_scenes.h"

namespace {

using namespace hapticut;

const mesh::SurfaceMesh& heart(int triangles) {
    static std::map<int, mesh::SurfaceMesh> cache;
    auto it = cache.find(triangles);
    if (it == cache.end()) {
        it = cache.emplace(triangles, scene::benchHeart(triangles).source.mesh).first;
    }
    return it->second;
}

void BM_BvhBuild(benchmark::State& state) {
    const mesh::SurfaceMesh& m = heart(static_cast<int>(state.range(0)));
    collision::Bvh bvh;
    for (auto _ : state) bvh.build({m.positions, m.faces});
}
BENCHMARK(BM_BvhBuild)->Arg(1619)->Arg(9714)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMicrosecond);

void BM_BvhRefit(benchmark::State& state) {
    const mesh::SurfaceMesh& m = heart(static_cast<int>(state.range(0)));
    collision::Bvh bvh;
    bvh.build({m.positions, m.faces});
    for (auto _ : state) bvh.refit({m.positions, m.faces});
}
BENCHMARK(BM_BvhRefit)->Arg(1619)->Arg(9714)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMicrosecond);

// The device slides over the front in contact (scene::slidingDevice_m): every update collides, slides
// and checks itself.
void BM_ProxyUpdateInContact(benchmark::State& state) {
    const mesh::SurfaceMesh& m = heart(static_cast<int>(state.range(0)));
    collision::Bvh bvh;
    const collision::SurfaceView view{m.positions, m.faces};
    bvh.build(view);
    const mesh::VertexFaces topology = mesh::buildVertexFaces(m.faces, m.positions.size());
    haptics::GodObjectProxy proxy(haptics::ProxyParams{.closedSurface = true});
    proxy.setTopology(&topology);  // as the loop's proxies have it
    proxy.reset(Vec3(0, 0, 0.2));
    long contacts = 0, step = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(proxy.update(scene::slidingDevice_m(++step), view, bvh));
        contacts += proxy.contact().active;
    }
    state.counters["contact_fraction"] = static_cast<double>(contacts) / static_cast<double>(state.iterations());
    state.counters["parity_fraction"] =
        static_cast<double>(proxy.paritySideChecks()) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ProxyUpdateInContact)->Arg(1619)->Arg(9714)->Arg(100'000)->Arg(1'000'000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
