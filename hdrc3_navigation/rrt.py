"""RRT-Connect on OMPL (chapter section 7.1.1), for online planning and roadmap reconnection.

The trees grow between one or more start states and one or more goal states (OMPL's
``GoalStates``): with a single start and goal this is the online RRT planner; with the nodes of
the two roadmap components that runtime constraints left apart, it is the §7.1.2 PRM+RRT
reconnection.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from ompl import base as ob
from ompl import geometric as og

from hdrc3_navigation.ompl_space import OmplSpace


def rrt_connect(
    space: OmplSpace,
    starts: Sequence[NDArray[np.float64]],
    goals: Sequence[NDArray[np.float64]],
    deadline: float,
    max_range: float = 60.0,
) -> NDArray[np.float64] | None:
    """An (n, 3) waypoint path from one of ``starts`` to one of ``goals``, or None.

    Stops at ``deadline`` (a ``time.perf_counter`` value); an approximate solution counts as
    none.
    """
    budget = deadline - time.perf_counter()
    if budget <= 0.0 or not starts or not goals:
        return None
    pdef = ob.ProblemDefinition(space.si)
    keep = []  # the states must outlive the query
    for p in starts:
        s = space.state(p)
        keep.append(s)
        pdef.addStartState(s)
    goal = ob.GoalStates(space.si)
    for p in goals:
        s = space.state(p)
        keep.append(s)
        goal.addState(s)
    pdef.setGoal(goal)
    planner = og.RRTConnect(space.si)
    planner.setRange(max_range)
    planner.setProblemDefinition(pdef)
    planner.setup()
    status = planner.solve(budget)
    if not pdef.hasExactSolution() or "Exact" not in str(status):
        return None
    return OmplSpace.path_points(pdef.getSolutionPath())
