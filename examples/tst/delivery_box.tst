# Mission leg II in miniature (chapter section 11.1.2): uav0 takes off from pad H1, flies to the
# supply depot, picks up box1 (food) with its winch and electromagnet, carries it to the west
# field and puts it down there. Boxes and carriers of the world file are places by their tag
# (`box1` below is where revinge.toml stocks it); the hook commands are ppcl_hook.
world revinge
agents uav0

point box1 = box1 at 0
point OverDepot = supply_depot at 20
point OverField = west_field at 20
point Field = west_field at 0

deliver(P, TS, TE) = with T1, T2, T3, T4, T5, T6, T7, T8 sequence
  to_depot(T1, T2) = fly-to(T1, T2, 6, OverDepot);
  pick(T3, T4) = pick-up-box(T3, T4, box1);
  carry(T5, T6) = fly-to(T5, T6, 4, OverField);
  put(T7, T8) = drop-box(T7, T8, box1, Field)
where P = uav0 and TS = 0 and TE <= 900
