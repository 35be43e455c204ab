"""Lateral analyses of a train at its speed: modes, Campbell diagram, unbalance response,
Floquet stability under the varying mesh stiffness, the periodic mesh response."""
