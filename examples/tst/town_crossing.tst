# A planned fly-to across revinge (chapter section 7, Figure 18): uav0 takes off from pad H1 and
# flies through the town to its east edge, south of the fire-training-ground no-fly zone. The
# path planner gives the segments; a no-fly zone declared during the flight
# (`hdrc3 path gis add-zone`) makes the executor replan the rest of the path.
world revinge
agents uav0

point EastEdge = (275, 20, 20)

mission(P, TS, TE) = with T1, T2, T3, T4 sequence
  up(T1, T2) = take-off(T1, T2);
  cross(T3, T4) = fly-to(T3, T4, 8, EastEdge)
where P = uav0 and TS = 0 and TE <= 600
