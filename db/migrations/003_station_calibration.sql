-- A station's calibration (devices/kinematics.h StationCalibration as JSON): per device its kind
-- (pen or scope), workspace mapping (scale, rotation, offset) and, for a scope, the portal.
-- Empty = the default (two pens, identity mappings). The server sends it in the agent's welcome.
ALTER TABLE stations ADD COLUMN calibration TEXT NOT NULL DEFAULT '';
