# Recovery from a box lost in flight (chapter sections 9.3 and 11.1.2). The goal node is planned
# by TALplanner: fly to the supply depot, pick up box1, carry it to the west field, drop it
# there (d/1 .. d/4). Run with a fault that releases the box in flight:
#
#   hdrc3 tst run examples/tst/delivery_box_drop.tst --launch --fault uav0:hook:release@fly-to#2+10
#
# The execution monitor's box_held formula (hdrc3_deliberative/default.monitors, Example 9.4 on
# the hook's carrying sensor) is violated when the sensor stops reporting box1; the TST manager
# suspends the flight, the aircraft hovers, the box-lost recovery operator puts box1 below the
# aircraft and TALplanner plans the rest again: pick it up there, carry it on, drop it.
world revinge
agents uav0

point box1 = box1 at 0
point OverDepot = supply_depot at 20
point OverField = west_field at 20

d(P, TS, TE) = goal at(box1, OverField) where P = uav0
