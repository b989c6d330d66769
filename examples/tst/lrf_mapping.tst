# Laser elevation mapping (chapter section 11.2): uav0 maps revinge's town block with the
# rotating laser range finder, the laser_mapper stores the map in its path planner's GIS, and a
# low flight through the corridor between B04 and B05 is then planned in the new map. Flown with
# `--sim-world revinge_changed` the world has a container (C1) in that corridor and new trees
# (V-new) that the stack's model (revinge) lacks: the map finds both, and the planner keeps its
# 6 m margin from the container that the model does not know.
world revinge
agents uav0

area TownBlock = polygon((-30, -75), (85, -75), (85, -10), (-30, -10))
point CorridorSouth = (6, -95, 7)
point CorridorNorth = (6, 8, 7)

mission(P, TS, TE) = with T1, T2, T3, T4, T5, T6 sequence
  survey(T1, T2) = laser-map-area(T1, T2, 6, TownBlock, 30);
  south(T3, T4) = fly-to(T3, T4, 5, CorridorSouth);
  north(T5, T6) = fly-to(T5, T6, 3, CorridorNorth)
where P = uav0 and TS = 0 and TE <= 900
