"""DyKnow stream reasoning middleware and temporal-logic execution monitoring (chapter 8, 9.3).

Streams, policies, state synchronisation, the ontology and semantic matching turn fluent samples
into states; the monitor formula language (:mod:`hdrc3_dyknow.formula`,
:mod:`hdrc3_dyknow.formula_parser`) and the progression engine (:mod:`hdrc3_dyknow.progression`)
evaluate metric temporal formulas incrementally over those states.
"""
