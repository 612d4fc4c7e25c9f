// Boost Graph's howard_cycle_ratio (maximum_cycle_ratio) on an .edges file.
// Prints one JSON line: solve time (file reading and graph building excluded),
// Howard iterations (counted by a second, instrumented run of the same loop),
// the float ratio, the exact ratio of the critical cycle Boost returns, and
// the peak resident memory of the process.
#include <chrono>
#include <cstdio>
#include <sys/resource.h>
#include <vector>
#include <boost/graph/adjacency_list.hpp>
#include "edges_reader.hpp"
// Instrumentation only: the iteration counter of ocr_howard is a local
// variable; opening the class lets a copy of its loop count the rounds.
#define private public
#include <boost/graph/howard_cycle_ratio.hpp>
#undef private

using namespace boost;
typedef adjacency_list<vecS, vecS, directedS, no_property,
    property<edge_weight_t, double, property<edge_weight2_t, double,
    property<edge_index_t, int>>>> Graph;
typedef graph_traits<Graph>::edge_descriptor Edge;

int main(int argc, char** argv) {
    if (argc < 2) { std::fprintf(stderr, "usage: boost_howard FILE.edges\n"); return 2; }
    ArcList a = read_edges(argv[1]);
    Graph g(a.n);
    for (size_t k = 0; k < a.src.size(); ++k) {
        Edge e = add_edge(a.src[k], a.dst[k], g).first;
        put(edge_weight, g, e, (double)a.weight[k]);
        put(edge_weight2, g, e, (double)a.tokens[k]);
        put(edge_index, g, e, (int)k);
    }
    std::vector<Edge> cycle;
    auto t0 = std::chrono::steady_clock::now();
    double ratio = maximum_cycle_ratio(g, get(vertex_index, g), get(edge_weight, g),
                                       get(edge_weight2, g), &cycle);
    auto t1 = std::chrono::steady_clock::now();
    double seconds = std::chrono::duration<double>(t1 - t0).count();
    struct rusage ru; getrusage(RUSAGE_SELF, &ru);
    long peak_kib = ru.ru_maxrss;
    // Exact ratio of the critical cycle Boost found (integers summed exactly).
    __int128 sw = 0, st = 0;
    for (const Edge& e : cycle) {
        int k = get(edge_index, g, e);
        sw += a.weight[k]; st += a.tokens[k];
    }
    long long num = (long long)sw, den = (long long)st;
    long long gg = den ? gcd_ll(num, den) : 1;
    if (gg) { num /= gg; den /= gg; }
    // Iterations: the same loop as mcr_howard::ocr_howard, with a counter.
    typedef detail::float_wrapper<mcr_float<>, detail::max_comparator_props<mcr_float<>>> Traits;
    detail::mcr_howard<Traits, Graph, property_map<Graph, vertex_index_t>::type,
        property_map<Graph, edge_weight_t>::type, property_map<Graph, edge_weight2_t>::type>
        howard(g, get(vertex_index, g), get(edge_weight, g), get(edge_weight2, g));
    howard.construct_policy_graph();
    int k = 0;
    double mcr;
    do { mcr = howard.policy_mcr(); ++k; } while (howard.try_improve_policy(mcr) && k < 100);
    std::printf("{\"solver\": \"boost\", \"seconds\": %.6f, \"iterations\": %d, \"capped\": %s, "
                "\"float_ratio\": %.17g, \"ratio\": \"%lld/%lld\", \"cycle_arcs\": %zu, "
                "\"peak_kib\": %ld}\n", seconds, k, k >= 100 ? "true" : "false", ratio, num, den,
                cycle.size(), peak_kib);
    return 0;
}
