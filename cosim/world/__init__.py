"""What is simulated around the ECU: the plant FMU, the actuator gateway, the driver, the radar and the objects."""
