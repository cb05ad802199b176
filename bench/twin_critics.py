"""Two critics as two networks (the anchor) or as one batched stack: the cost of a critic update.

DiscreteSAC's critic is two Q-networks; each update runs them (and their targets) one after the
other. Stacking their weights as (2, in, out) tensors runs both in one ``baddbmm`` per layer.
This times forward + backward + fused Adam of a plain MLP critic pair ([64, 64] hidden, batch
256, PlanningStraight-sized input of 30 and 5 actions, one torch thread), median of rounds that
alternate between the two forms, and prints the ratio. A measurement for a lead, not a feature:
the package's critics are still two networks (docs/ablation/README.md, "Where the study's time
goes").

Usage: python bench/twin_critics.py [--repeats 3] [--updates 2000]
"""

from __future__ import annotations

import argparse
import statistics
import time

import torch as th
from dsac_update import positive_int  # bench/ is the script's folder
from torch import nn

BATCH, IN, HIDDEN, ACTIONS = 256, 30, 64, 5


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=positive_int, default=3)
    parser.add_argument("--updates", type=positive_int, default=2000)
    args = parser.parse_args()
    th.set_num_threads(1)
    th.manual_seed(0)
    x, target = th.randn(BATCH, IN), th.randn(BATCH, ACTIONS)
    two = [
        nn.Sequential(
            nn.Linear(IN, HIDDEN), nn.ReLU(), nn.Linear(HIDDEN, HIDDEN), nn.ReLU(),
            nn.Linear(HIDDEN, ACTIONS),
        )
        for _ in range(2)
    ]  # fmt: skip
    sizes = [IN, HIDDEN, HIDDEN, ACTIONS]
    weights = [nn.Parameter(th.randn(2, a, b) * 0.1) for a, b in zip(sizes, sizes[1:])]
    biases = [nn.Parameter(th.zeros(2, 1, b)) for b in sizes[1:]]
    two_opt = th.optim.Adam([p for net in two for p in net.parameters()], fused=True)
    stack_opt = th.optim.Adam(weights + biases, fused=True)

    def two_networks() -> None:
        loss = sum(((net(x) - target) ** 2).mean() for net in two)
        two_opt.zero_grad()
        loss.backward()
        two_opt.step()

    def one_stack() -> None:
        h = x.unsqueeze(0).expand(2, BATCH, IN)
        for i, (w, b) in enumerate(zip(weights, biases)):
            h = th.baddbmm(b, h, w)
            if i < len(weights) - 1:
                h = th.relu(h)
        loss = ((h - target) ** 2).mean(dim=(1, 2)).sum()
        stack_opt.zero_grad()
        loss.backward()
        stack_opt.step()

    def cost_us(update) -> float:
        for _ in range(100):
            update()
        start = time.process_time()
        for _ in range(args.updates):
            update()
        return (time.process_time() - start) / args.updates * 1e6

    rounds: dict[str, list[float]] = {"two networks (anchor)": [], "one batched stack": []}
    for _ in range(args.repeats):
        rounds["two networks (anchor)"].append(cost_us(two_networks))
        rounds["one batched stack"].append(cost_us(one_stack))
    anchor = statistics.median(rounds["two networks (anchor)"])
    print(f"critic pair [64, 64], batch {BATCH}, one thread (median of {args.repeats} rounds):")
    for name, values in rounds.items():
        us = statistics.median(values)
        print(f"  {name:<22} {us:7.0f} us per update  ({us / anchor:.2f}x)")


if __name__ == "__main__":
    main()
