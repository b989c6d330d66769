# Recovery from a load too heavy to lift (chapter sections 9.3, 9.3.1 and 11.1.2). revinge's
# carrier3 stands in the carrier depot with four boxes of 5 kg on it, 28 kg in all. The planner
# assumes the RMAX lifts 30 kg; the hook's winch is rated 24 kg. Two goal nodes, each planned
# by TALplanner, bring box7 and box10 to the yard south of the depot:
#
#   hdrc3 tst run examples/tst/delivery_carrier_overweight.tst --launch
#
# The first plan lifts the carrier with all four boxes. The winch stalls under it, and the
# execution monitor's carrier_lifted formula (hdrc3_deliberative/default.monitors) is violated
# after a second: the TST manager suspends the pick-up, the aircraft hovers, the
# carrier-too-heavy recovery operator (hdrc3_tst/default.recovery) lowers the lift capacity to
# 0.8 x 28 = 22.4 kg, and TALplanner plans again with fewer boxes: box7 alone on the hook. The
# lowered capacity holds for the later goal: box10 flies on the hook too (the 23 kg left on the
# carrier are still too much). A third goal (box9) would lift the carrier with the 18 kg left;
# it is left out here because nothing watches the boxes on a carrier in flight yet, and one
# that slides off fails the goal that wants it.
world revinge
agents uav0

point carrier3 = carrier3 at 0
point box7 = box7 at 0
point box8 = box8 at 0
point box9 = box9 at 0
point box10 = box10 at 0
point OverDepot = carrier_depot at 20
point Yard = (-230, 70, 20)

d(P, TS, TE) = with T1, T2, T3, T4 sequence
  first(T1, T2) = goal at(box7, Yard);
  second(T3, T4) = goal at(box10, Yard)
where P = uav0
