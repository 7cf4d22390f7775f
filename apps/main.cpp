#include <iostream>
int main() { std::cout << "imuconv\n"; return 0; }
