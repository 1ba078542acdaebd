/* tests/tables.h - the one list of test files: TEST_TABLE(x) for each
   tests/test_x.c, which exports the NULL-terminated table
   `const TestCase tests_x[]`.  A new test file needs one line here and nothing
   else: test.h declares the tables from this list, tests/runner.c runs them in
   this order, and the Makefile compiles every .c file of tests/.  tests/run.sh
   (repo_test_tables) fails when a tests/test_x.c is missing here.  No include
   guard: each user defines TEST_TABLE(x) before including this file. */
TEST_TABLE(util)
TEST_TABLE(bvh)
TEST_TABLE(spectrum)
TEST_TABLE(scene)
TEST_TABLE(image)
TEST_TABLE(material)
TEST_TABLE(render)
TEST_TABLE(lights)
TEST_TABLE(scenes)
TEST_TABLE(physics)
TEST_TABLE(robust)
TEST_TABLE(lighttree)
TEST_TABLE(pbrt)
TEST_TABLE(wavelengths)
TEST_TABLE(sampler)
TEST_TABLE(fluor)
TEST_TABLE(delta)
TEST_TABLE(texture)
TEST_TABLE(shapes)
TEST_TABLE(filter)
TEST_TABLE(png)
TEST_TABLE(exr)
TEST_TABLE(conductor)
TEST_TABLE(coated)
TEST_TABLE(medium)
TEST_TABLE(grid)
TEST_TABLE(notes)
TEST_TABLE(mix)
TEST_TABLE(subdiv)
TEST_TABLE(patch)
TEST_TABLE(overlap)
TEST_TABLE(instance)
