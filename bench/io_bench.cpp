// Google Benchmark: reading and writing the thesis model format.
#include <benchmark/benchmark.h>

#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/scene/bench_scenes.h"

namespace {

using namespace hapticut;

void BM_ParseThesisModel(benchmark::State& state) {
    const scene::Scene heart = scene::benchHeart(static_cast<int>(state.range(0)));
    const std::string text = mesh::io::formatModel(heart.source.mesh, heart.source.physics);
    for (auto _ : state) benchmark::DoNotOptimize(mesh::io::parseModel(text, "heart.txt"));
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
}
BENCHMARK(BM_ParseThesisModel)->Arg(1619)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
