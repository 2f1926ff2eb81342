"""PSYONIC: the Ability Hand (:mod:`robot_agents.robots.psyonic.ability_hand`)."""
