"""The core names objects, materials, lights and bake points by its own numbers; the add-on
puts Blender's names in their place before a message reaches the user."""

from bakegi.export.targets import BakeTarget, name_elements


def test_core_numbers_become_blender_names():
    targets = [BakeTarget("Floor", "FloorMesh", "CORNER", 0, 100),
               BakeTarget("Cube", "CubeMesh", "POINT", 100, 24)]
    message = ("mesh 2 (object 1): 3 triangles dropped; material 0: albedo is NaN; "
               "light 1 (spot): color is infinite; bake point 110: normal is the zero vector")
    named = name_elements(message, ["Floor", "Cube"], ["Wood"], ["Key", "Rim"], targets)
    assert named == ("mesh 2 (object 'Cube'): 3 triangles dropped; material 'Wood': albedo is "
                     "NaN; light 'Rim' (spot): color is infinite; bake point 110 (object "
                     "'Cube'): normal is the zero vector")


def test_numbers_without_a_name_stay():
    message = "material 4: albedo is NaN; light 7: bad; bake point 999: bad; lights 2"
    assert name_elements(message, [], ["Wood"], ["Key"], []) == message
