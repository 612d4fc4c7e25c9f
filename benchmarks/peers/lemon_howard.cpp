// LEMON's HowardMmc on an .edges file whose arcs all carry the same token count.
// HowardMmc finds a minimum mean cycle (cost / number of arcs); it has no ratio
// variant, so the maximum cycle ratio is -min mean(-w) / t, valid only when
// every arc carries the same t tokens (exit 3 otherwise). Prints one JSON line.
#include <chrono>
#include <cstdio>
#include <sys/resource.h>
#include <lemon/howard_mmc.h>
#include <lemon/smart_graph.h>
#include "edges_reader.hpp"

int main(int argc, char** argv) {
    if (argc < 2) { std::fprintf(stderr, "usage: lemon_howard FILE.edges\n"); return 2; }
    ArcList a = read_edges(argv[1]);
    long long t = a.tokens.empty() ? 1 : a.tokens[0];
    for (long long x : a.tokens) if (x != t || t <= 0) {
        std::fprintf(stderr, "lemon_howard: arcs carry different token counts; HowardMmc "
                             "computes cycle means, not ratios\n");
        return 3;
    }
    lemon::SmartDigraph g;
    g.reserveNode(a.n); g.reserveArc(a.src.size());
    for (long long v = 0; v < a.n; ++v) g.addNode();
    lemon::SmartDigraph::ArcMap<long long> cost(g);
    for (size_t k = 0; k < a.src.size(); ++k) {
        auto arc = g.addArc(g.nodeFromId(a.src[k]), g.nodeFromId(a.dst[k]));
        cost[arc] = -a.weight[k];  // maximum mean of w = -(minimum mean of -w)
    }
    auto t0 = std::chrono::steady_clock::now();
    lemon::HowardMmc<lemon::SmartDigraph, lemon::SmartDigraph::ArcMap<long long>> mmc(g, cost);
    bool found = mmc.findCycleMean();
    auto t1 = std::chrono::steady_clock::now();
    double seconds = std::chrono::duration<double>(t1 - t0).count();
    struct rusage ru; getrusage(RUSAGE_SELF, &ru);
    long long num = found ? -(long long)mmc.cycleCost() : 0;
    long long den = found ? (long long)mmc.cycleSize() * t : 0;
    long long gg = den ? gcd_ll(num, den) : 1;
    if (gg) { num /= gg; den /= gg; }
    std::printf("{\"solver\": \"lemon\", \"seconds\": %.6f, \"iterations\": null, "
                "\"float_ratio\": %.17g, \"ratio\": \"%lld/%lld\", \"peak_kib\": %ld}\n",
                seconds, found ? -mmc.cycleMean() / t : 0.0, num, den, (long)ru.ru_maxrss);
    return 0;
}
