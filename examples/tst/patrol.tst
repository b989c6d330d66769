# The other node types: a library TST used by `call`, a goal node that a task planner expands,
# a conditional, a loop and a concurrent for-each over the answers of a query.
world revinge
agents uav0, uav1

point Depot = supply_depot at 25
point Square = town_square at 30

hop(TS, TE) = with S fly-to(TS, TE, S, Square) where S <= 10

patrol(P, TS, TE) = with T1, T2, T3, T4, T5, T6, T7, T8 sequence
  go(T1, T2) = call hop(T1, T2);
  check(T3, T4) = if [T3] not low-battery(P) then
    again(T3, T4) = hover(T3, T4, 30)
  else
    home(T3, T4) = fly-to(T3, T4, 5, Depot)
  where true;
  watch(T5, T6) = while [T5] daylight() lookout(T5, T6) = look-at(T5, T6, Square)
  where T6 - T5 <= 600;
  each(T7, T8) = with P2 foreach Who where [T7] seen(Who) do conc
    deliver(P2, T7, T8) = goal delivered(Who, Depot)
  where P2 in {uav0, uav1}
where P = uav0 and TS = 0 and TE <= 3600
